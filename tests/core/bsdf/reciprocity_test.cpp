// Reciprocity: f(wi -> wo) / eta_o² = f(wo -> wi) / eta_i² within MC error (4 sigma) for both
// height models: the uncorrelated walk (supplement §2.1) and the correlated one, whose walk has
// the law of Heitz et al. 2016's explicit-height walk (reciprocal; the supplement's eq. 17 walk
// was not, §2.2). The renderer lights with eval (a walk from the light) and samples paths with
// sample (a walk from the viewer), so this is what makes the two see one BSDF.
// Sample/eval consistency: the weights of MicrofacetBsdf::sample, binned over wi, match the
// integral of eval(wo, wi) |cos wi| over each bin (chi-square with both variances, p ~ 1e-4),
// for every model the renderer builds: three facet types × GGX/Beckmann × both height models,
// and single scattering.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "core/bsdf/bsdf.h"
#include "tests/core/bsdf/stats.h"

namespace penumbra::bsdf {
namespace {

struct Mean {
  double value = 0, sigma = 0;
};

// Mean of n eval estimates of f(wi -> wo) (red channel), times scale.
Mean meanF(const WalkParams& p, const Vec3& wi, const Vec3& wo, int n, Rng& rng, double scale) {
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    const double v = estimateExitDensity(p, wi, wo, rng).x / std::abs(wo.z) * scale;
    s += v;
    s2 += v * v;
  }
  const double m = s / n;
  return {m, std::sqrt(std::max(0.0, s2 / n - m * m) / n)};
}

Vec3 dir(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

WalkParams params(Facets facets, HeightModel height, Ndf ndf = Ndf::GGX) {
  WalkParams p;
  p.surface = Microsurface{ndf, 1.0, 1.0};
  p.facets = facets;
  p.height = height;
  p.eta = Vec3(0.2, 0.4, 1.4);  // a gold-like conductor
  p.k = Vec3(3.6, 2.4, 1.8);
  p.albedo = Vec3(0.8);
  return p;
}

// Pairs (wi, wo): reflection at several elevations; for the dielectric also transmission.
std::vector<std::pair<Vec3, Vec3>> pairs(Facets facets) {
  std::vector<std::pair<Vec3, Vec3>> out = {{dir(0.2, 0), dir(1.0, 2.0)}, {dir(0.7, 0.5), dir(1.3, 3.0)},
                                            {dir(1.2, 0), dir(0.4, 1.0)}};
  if (facets == Facets::Dielectric) {
    out.push_back({dir(0.5, 0), dir(kPi - 0.4, 2.5)});
    out.push_back({dir(1.1, 0), dir(kPi - 0.9, 3.0)});
  }
  return out;
}

double eta2(const WalkParams& p, const Vec3& w) { return w.z < 0 ? p.ior * p.ior : 1.0; }

TEST(Reciprocity, HoldsForBothHeightModels) {
  Rng rng(21);
  for (HeightModel height : {HeightModel::Uncorrelated, HeightModel::Correlated})
    for (Facets facets : {Facets::Conductor, Facets::Dielectric, Facets::RoughDiffuse}) {
      const WalkParams p = params(facets, height);
      for (const auto& [wi, wo] : pairs(facets)) {
        const Mean a = meanF(p, wi, wo, 100000, rng, 1 / eta2(p, wo));
        const Mean b = meanF(p, wo, wi, 100000, rng, 1 / eta2(p, wi));
        const double sigma = std::hypot(a.sigma, b.sigma);
        std::printf("%s facets %d wi.z %+.3f wo.z %+.3f: f(i,o) %.4f f(o,i) %.4f asymmetry %+.2f%% (sigma %.2f%%)\n",
                    height == HeightModel::Correlated ? "correlated  " : "uncorrelated", int(facets), wi.z, wo.z,
                    a.value, b.value, 100 * (a.value - b.value) / b.value, 100 * sigma / b.value);
        EXPECT_NEAR(a.value, b.value, 4 * sigma) << int(height) << " " << int(facets) << " wi.z " << wi.z << " wo.z " << wo.z;
        EXPECT_LT(sigma, 0.05 * a.value);
      }
    }
}

// The models walkParamsOf (core/render) builds: each facet type and NDF, both height models,
// multiple and single scattering.
std::vector<WalkParams> rendererModels() {
  std::vector<WalkParams> out;
  for (Facets facets : {Facets::Conductor, Facets::Dielectric, Facets::RoughDiffuse})
    for (Ndf ndf : {Ndf::GGX, Ndf::Beckmann}) {
      for (HeightModel height : {HeightModel::Correlated, HeightModel::Uncorrelated})
        out.push_back(params(facets, height, ndf));
      out.push_back(params(facets, HeightModel::Correlated, ndf));
      out.back().singleScattering = true;
    }
  return out;
}

std::string describe(const WalkParams& p) {
  return std::string(p.surface.ndf == Ndf::GGX ? "GGX " : "Beckmann ") + "facets " + std::to_string(int(p.facets)) +
         (p.height == HeightModel::Correlated ? " correlated" : " uncorrelated") + (p.singleScattering ? " single" : "");
}

TEST(SampleEval, SampledWeightsMatchEvalPerBin) {
  Rng rng(23);
  for (const WalkParams& p : rendererModels()) {
    const MicrofacetBsdf bsdf(p);
    const Facets facets = p.facets;
    const Vec3 wo = dir(0.8, 0.3);
    test::SphereBins bins{6, 8, facets != Facets::Dielectric ? 0.0 : -1.0, 1.0};
    const int n = 100000;
    std::vector<double> sum(bins.size(), 0.0), sum2(bins.size(), 0.0);
    for (int i = 0; i < n; ++i) {
      const std::optional<BsdfSample> s = bsdf.sample(wo, rng);
      if (!s) continue;
      const int b = bins.index(s->wi);
      ASSERT_GE(b, 0);
      sum[b] += s->weight.x;
      sum2[b] += s->weight.x * s->weight.x;
    }
    // ∫_bin f(wo, wi) |cos wi| dwi: m stratified eval estimates per bin.
    // The eval estimate is heavy-tailed in the faint transmitted bins: with 400 per bin their
    // means fall short (chi-square 122 for 48 bins); 4000 resolve them.
    const int m = facets == Facets::Dielectric ? 4000 : 1000;
    const double dz = (bins.zMax - bins.zMin) / bins.nz, dphi = 2 * kPi / bins.nphi;
    double chi = 0;
    int used = 0;
    for (int i = 0; i < bins.nz; ++i)
      for (int j = 0; j < bins.nphi; ++j) {
        double e = 0, e2 = 0;
        for (int k = 0; k < m; ++k) {
          const double z = bins.zMin + (i + rng.uniform()) * dz, phi = (j + rng.uniform()) * dphi;
          const double r = std::sqrt(std::max(0.0, 1 - z * z));
          const Vec3 wi(r * std::cos(phi), r * std::sin(phi), z);
          const double v = bsdf.eval(wo, wi, rng).x * std::abs(z) * dz * dphi;
          e += v;
          e2 += v * v;
        }
        const double evalMean = e / m, evalVar = std::max(0.0, e2 / m - evalMean * evalMean) / m;
        const int b = i * bins.nphi + j;
        const double sampleMean = sum[b] / n, sampleVar = std::max(0.0, sum2[b] / n - sampleMean * sampleMean) / n;
        if (sampleMean * n < 20) continue;  // too few samples for a normal approximation
        chi += (sampleMean - evalMean) * (sampleMean - evalMean) / (sampleVar + evalVar);
        ++used;
      }
    std::printf("sample/eval %s: chi-square %.1f over %d bins (threshold %.1f)\n", describe(p).c_str(), chi, used,
                test::chiSquareThreshold(used));
    EXPECT_GT(used, 20) << describe(p);
    EXPECT_LT(chi, test::chiSquareThreshold(used)) << describe(p) << " bins " << used;
  }
}

}  // namespace
}  // namespace penumbra::bsdf
