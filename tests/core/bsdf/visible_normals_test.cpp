// Sampling of visible normals over the whole sphere of directions: samples face ω and lie above
// the macrosurface; their histogram matches visibleNormalPdf (chi-square, p ~ 1e-4), whose
// integral is 1 (projectedArea is its normalisation).
#include <gtest/gtest.h>

#include <numbers>

#include "core/bsdf/microsurface.h"
#include "core/bsdf/rng.h"
#include "tests/core/bsdf/stats.h"

namespace penumbra::bsdf {
namespace {

TEST(VisibleNormals, HistogramMatchesPdfFromAboveAndBelow) {
  Rng rng(7);
  test::SphereBins bins{12, 16, 0.0, 1.0};
  const int n = 100000;
  for (Ndf ndf : {Ndf::GGX, Ndf::Beckmann}) {
    for (const Microsurface s : {Microsurface{ndf, 0.5, 0.5}, Microsurface{ndf, 1.0, 0.3}}) {
      for (double theta : {0.2, 1.0, 1.5, 1.8, 2.4}) {
        const Vec3 w(std::sin(theta) * std::cos(0.7), std::sin(theta) * std::sin(0.7), std::cos(theta));
        std::vector<double> observed(bins.size(), 0.0);
        for (int i = 0; i < n; ++i) {
          const double u1 = rng.uniform(), u2 = rng.uniform();
          const Vec3 m = s.sampleVisibleNormal(w, u1, u2);
          ASSERT_GT(m.z, 0);
          ASSERT_GE(glm::dot(m, w), -1e-9);
          ASSERT_NEAR(glm::length(m), 1.0, 1e-9);
          observed[bins.index(m)] += 1;
        }
        std::vector<double> expected = bins.integrate([&](const Vec3& m) { return s.visibleNormalPdf(w, m); }, 40);
        double mass = 0;
        for (double& e : expected) {
          mass += e;
          e *= n;
        }
        const std::string where = std::string(ndf == Ndf::GGX ? "GGX" : "Beckmann") + " alpha (" +
                                  std::to_string(s.alphaX) + ", " + std::to_string(s.alphaY) +
                                  ") theta " + std::to_string(theta);
        EXPECT_NEAR(mass, 1.0, 5e-3) << where;
        int dof = 0;
        const double chi = test::chiSquare(observed, expected, dof);
        EXPECT_LT(chi, test::chiSquareThreshold(dof)) << where << " dof " << dof;
      }
    }
  }
}

}  // namespace
}  // namespace penumbra::bsdf
