// The position-free walk against the independent height-sampling walk (bench/lib/heitz_walk.h,
// Heitz et al. 2016), per bounce order, at the supplement's incident angles 0, 0.5, 1.0, 1.5 rad.
// Statistics over exit-direction histograms (12 cos θ × 12 φ bins over the sphere):
// - every order (1, 2, 3+), height-correlated: the walk carries its vertices' heights, so its law
//   is the reference's: a two-sample chi-square at p ~ 1e-4 for each;
// - at 1.5 rad the height-uncorrelated model is further from the reference than the correlated
//   one (the supplement's observation: its differences are largest at grazing angles).
// bench: build/penumbra-bsdf-bench prints every order and configuration (README "Materials").
#include <gtest/gtest.h>

#include <cmath>

#include "bench/lib/bsdf_lobes.h"
#include "tests/core/bsdf/stats.h"

namespace penumbra::bsdf {
namespace {

using bench::LobeConfig;
using bench::Lobes;

TEST(LobesVsHeitz, EveryOrderMatchesAndUncorrelatedIsFurtherAtGrazing) {
  const int walks = 40000;
  uint64_t seed = 100;
  for (Facets facets : {Facets::Conductor, Facets::Dielectric, Facets::RoughDiffuse}) {
    for (const auto& [ax, ay] : {std::pair{0.5, 0.5}, std::pair{1.0, 1.0}, std::pair{1.0, 0.1}}) {
      for (double theta : {0.0, 0.5, 1.0, 1.5}) {
        const LobeConfig c{facets, ax, ay, theta};
        const Lobes ref = bench::heitzLobes(c, walks, seed++);
        const Lobes corr = bench::walkLobes(c, HeightModel::Correlated, walks, seed++);
        for (int order = 0; order < Lobes::kOrders; ++order) {
          int dof = 0;
          const double chi = bench::twoSampleChiSquare(corr, ref, order, dof);
          if (dof < 1) continue;
          EXPECT_LT(chi, test::chiSquareThreshold(dof)) << c.name() << " order " << order + 1 << " dof " << dof;
        }
        if (theta != 1.5 || facets == Facets::Dielectric) continue;
        const Lobes unc = bench::walkLobes(c, HeightModel::Uncorrelated, walks, seed++);
        const double corrL1 = bench::relativeL1(corr, ref, 1), uncL1 = bench::relativeL1(unc, ref, 1);
        EXPECT_GT(uncL1, corrL1) << c.name();
        EXPECT_GT(bench::relativeL1(unc, ref, 0), bench::relativeL1(corr, ref, 0)) << c.name();
      }
    }
  }
}

}  // namespace
}  // namespace penumbra::bsdf
