// Eq. 3 (closed-form full-sphere G1) against the numerical integral of eq. 4 over the microfacet
// normals, for GGX and Beckmann, alpha in {0.25, 0.5, 1}, directions over the whole sphere.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/bsdf/microsurface.h"

namespace penumbra::bsdf {
namespace {

// ∫_0^{2π} max(0, A cos ψ + B) dψ (A >= 0): the azimuthal part of eq. 4 for an isotropic D.
double clampedCosineAroundAzimuth(double a, double b) {
  if (b >= a) return 2 * kPi * b;
  if (b <= -a) return 0;
  const double psi0 = std::acos(-b / a);
  return 2 * (a * std::sin(psi0) + b * psi0);
}

// ∫_{Ω+} <ω, m> D(m) dm for an isotropic D: the azimuth in closed form, θ_m by the midpoint rule
// in u with θ_m = atan(α tan(πu/2)) (dense where D is, out to the GGX tails at θ_m = π/2).
// Seen from below, only facets tilted by more than θ_ω - π/2 face ω: the grid starts there.
double integratedProjectedArea(const Microsurface& s, const Vec3& w, int nu) {
  const double a = s.alphaX;
  const double thetaMin = std::max(0.0, std::acos(w.z) - 0.5 * kPi);
  const double uMin = 2 / kPi * std::atan(std::tan(thetaMin) / a);
  const double sinW = std::sqrt(std::max(0.0, 1 - w.z * w.z));
  double sum = 0;
  for (int i = 0; i < nu; ++i) {
    const double u = uMin + (1 - uMin) * (i + 0.5) / nu;
    const double slope = std::tan(0.5 * kPi * u);
    const double theta = std::atan(a * slope);
    const double dThetaDu = a * 0.5 * kPi * (1 + slope * slope) / (1 + a * a * slope * slope);
    const double st = std::sin(theta), ct = std::cos(theta);
    const double d = s.D(Vec3(st, 0, ct));
    sum += d * clampedCosineAroundAzimuth(sinW * st, w.z * ct) * st * dThetaDu;
  }
  return sum * (1 - uMin) / nu;
}

TEST(G1Sphere, ClosedFormMatchesIntegralOverTheWholeSphere) {
  for (Ndf ndf : {Ndf::GGX, Ndf::Beckmann}) {
    for (double alpha : {0.25, 0.5, 1.0}) {
      const Microsurface s{ndf, alpha, alpha};
      int above = 0, belowOverOne = 0;
      for (int deg = 0; deg <= 170; deg += 5) {
        if (deg == 90) continue;  // G1 = 0 on the horizon from both sides
        const double t = deg * kPi / 180, phi = 0.3;
        const Vec3 w(std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t));
        const double area = integratedProjectedArea(s, w, 40000);
        const double closed = s.g1Dist(w);
        if (!(area > 1e-280)) continue;  // Beckmann seen from far below: no facet faces ω in double
        const double numeric = std::abs(w.z) / area;  // eq. 4
        EXPECT_NEAR(closed / numeric, 1.0, 1e-5)
            << (ndf == Ndf::GGX ? "GGX" : "Beckmann") << " alpha " << alpha << " theta " << deg;
        EXPECT_NEAR(s.projectedArea(w) / area, 1.0, 1e-5);
        if (w.z > 0) {
          ++above;
          EXPECT_LE(closed, 1.0);
        } else if (closed > 1.0) {
          ++belowOverOne;
        }
      }
      EXPECT_GT(above, 10);
      EXPECT_GT(belowOverOne, 0) << "eq. 3: G1 exceeds 1 below the macrosurface";
    }
  }
}

TEST(G1Sphere, LambdaIsExtendedOddlyAroundMinusOneHalf) {
  for (Ndf ndf : {Ndf::GGX, Ndf::Beckmann}) {
    const Microsurface s{ndf, 0.3, 0.8};
    for (int i = 1; i < 40; ++i) {
      const double t = i * kPi / 80, phi = 0.17 * i;
      const Vec3 w(std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t));
      EXPECT_NEAR(s.lambda(w) + s.lambda(-w), -1.0, 1e-12);
      EXPECT_GE(s.lambda(w), 0.0);
    }
  }
}

}  // namespace
}  // namespace penumbra::bsdf
