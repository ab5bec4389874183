// White furnace: with F = 1 (conductor) or albedo 1 (rough diffuse) all the light is reflected,
// and a dielectric reflects and transmits all of it, E_r + E_t = 1: the exit density estimated by
// the walk integrates to 1 over the sphere within MC error (4 sigma). Single scattering loses
// energy visibly at alpha = 1.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include "core/bsdf/walk.h"

namespace penumbra::bsdf {
namespace {

struct Estimate {
  double mean = 0, sigma = 0;  // sigma: standard error of the mean
};

// A direction from the first bounce's density (firstBounceDensity), as the walk's first vertex
// scatters: visible normal, then mirror or (dielectric, by Fresnel) refraction.
Vec3 sampleFirstBounce(const WalkParams& p, const Vec3& wi, Rng& rng) {
  if (p.facets == Facets::RoughDiffuse) {
    const double r = std::sqrt(rng.uniform()), phi = 2 * kPi * rng.uniform();
    return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1 - r * r))};
  }
  const double side = wi.z > 0 ? 1 : -1;
  const Vec3 w = side * wi;
  const double u1 = rng.uniform(), u2 = rng.uniform();
  const Vec3 m = p.surface.sampleVisibleNormal(w, u1, u2);
  const Vec3 mirror = 2 * glm::dot(w, m) * m - w;
  if (p.facets == Facets::Conductor) return side * mirror;
  const double eta = side > 0 ? p.ior : 1 / p.ior, c = glm::dot(w, m);
  const double s2 = (1 - c * c) / (eta * eta);
  if (s2 >= 1) return side * mirror;
  const double ct = std::sqrt(1 - s2);
  const double rs = (c - eta * ct) / (c + eta * ct), rp = (eta * c - ct) / (eta * c + ct);
  if (rng.uniform() < 0.5 * (rs * rs + rp * rp)) return side * mirror;
  return side * glm::normalize(-w / eta + (c / eta - ct) * m);
}

// ∫ estimateExitDensity(wi, wo) dwo over the sphere (red channel), wo drawn half the time
// uniformly on the sphere and half the time from the first bounce (one-sample mixture).
Estimate albedo(const WalkParams& p, const Vec3& wi, int n, Rng& rng) {
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    Vec3 wo;
    if (rng.uniform() < 0.5) {
      const double z = 1 - 2 * rng.uniform(), phi = 2 * kPi * rng.uniform();
      const double r = std::sqrt(std::max(0.0, 1 - z * z));
      wo = Vec3(r * std::cos(phi), r * std::sin(phi), z);
    } else {
      wo = sampleFirstBounce(p, wi, rng);
    }
    const double pdf = 0.5 / (4 * kPi) + 0.5 * firstBounceDensity(p, wi, wo);
    const double v = estimateExitDensity(p, wi, wo, rng).x / pdf;
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n)};
}

Vec3 direction(double theta) { return {std::sin(theta), 0.0, std::cos(theta)}; }

std::string describe(const WalkParams& p, double theta) {
  static const char* facets[] = {"rough diffuse", "conductor", "dielectric"};
  return std::string(facets[int(p.facets)]) + (p.surface.ndf == Ndf::GGX ? " GGX" : " Beckmann") +
         " alpha (" + std::to_string(p.surface.alphaX) + ", " + std::to_string(p.surface.alphaY) + ") " +
         (p.height == HeightModel::Correlated ? "correlated" : "uncorrelated") + " theta " + std::to_string(theta);
}

TEST(WhiteFurnace, MultipleBouncesKeepAllTheEnergy) {
  Rng rng(11);
  for (Facets facets : {Facets::Conductor, Facets::RoughDiffuse, Facets::Dielectric}) {
    for (HeightModel height : {HeightModel::Correlated, HeightModel::Uncorrelated}) {
      for (const auto& [ndf, ax, ay] : {std::tuple{Ndf::GGX, 1.0, 1.0}, std::tuple{Ndf::Beckmann, 0.5, 0.5},
                                        std::tuple{Ndf::GGX, 1.0, 0.1}}) {
        WalkParams p;
        p.surface = Microsurface{ndf, ax, ay};
        p.facets = facets;
        p.height = height;
        p.unitFresnel = true;
        for (double theta : {0.0, 1.0, 1.5}) {
          const Estimate e = albedo(p, direction(theta), 40000, rng);
          // The eval estimate is heavy-tailed (later bounces' densities peak sharply): sigma is
          // ~0.005-0.04 here, so 4 sigma resolves energy errors of 2-16 %.
          EXPECT_LT(e.sigma, 0.05) << describe(p, theta);
          EXPECT_NEAR(e.mean, 1.0, 4 * e.sigma) << describe(p, theta) << " sigma " << e.sigma;
        }
      }
    }
  }
}

// Light from inside a dielectric: the eval estimate's variance is unbounded there (the refraction
// Jacobian of later bounces has integrable peaks the mixture does not follow), so the energy is
// counted on sampled walks: none is lost, E_r + E_t = 1 (E_t: leaving on the other side).
TEST(WhiteFurnace, DielectricWalksLoseNothingFromEitherSide) {
  Rng rng(13);
  for (HeightModel height : {HeightModel::Correlated, HeightModel::Uncorrelated}) {
    WalkParams p;
    p.surface = Microsurface{Ndf::GGX, 1.0, 1.0};
    p.facets = Facets::Dielectric;
    p.height = height;
    for (double theta : {0.0, 1.0, 1.5, kPi - 1.5, kPi - 1.0, kPi}) {
      const Vec3 wi = direction(theta);
      double reflected = 0, transmitted = 0;
      const int n = 20000;
      for (int i = 0; i < n; ++i) {
        const std::optional<WalkExit> e = sampleWalk(p, wi, rng);
        ASSERT_TRUE(e) << describe(p, theta);
        ASSERT_NEAR(glm::length(e->direction), 1.0, 1e-9);
        ((e->direction.z > 0) == (wi.z > 0) ? reflected : transmitted) += e->weight.x;
      }
      EXPECT_DOUBLE_EQ((reflected + transmitted) / n, 1.0) << describe(p, theta);
      EXPECT_GT(transmitted, 0) << describe(p, theta);
    }
  }
}

TEST(WhiteFurnace, SingleScatteringLosesEnergyAtAlphaOne) {
  Rng rng(12);
  WalkParams p;
  p.surface = Microsurface{Ndf::GGX, 1.0, 1.0};
  p.unitFresnel = true;
  p.singleScattering = true;
  for (double theta : {0.0, 1.0}) {
    const Estimate e = albedo(p, direction(theta), 20000, rng);
    EXPECT_LT(e.mean, 0.9) << theta;
    EXPECT_LT(e.mean + 10 * e.sigma, 1.0) << theta;
  }
}

}  // namespace
}  // namespace penumbra::bsdf
