#include "core/bsdf/microsurface.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace penumbra::bsdf {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Squared "projected roughness × tan θ": (αx² ωx² + αy² ωy²) / ωz².
double stretchedTan2(const Microsurface& s, const Vec3& w) {
  const double a = s.alphaX * w.x, b = s.alphaY * w.y;
  return (a * a + b * b) / (w.z * w.z);
}

// Beckmann visible-slope CDF along the incident azimuth (alpha = 1, slopes x < mu = cot θ):
// ∫_{-inf}^{x} (mu - s) exp(-s²) / sqrt(pi) ds.
double beckmannSlopeCdf(double x, double mu) {
  return 0.5 * mu * std::erfc(-x) + std::exp(-x * x) / (2.0 * std::sqrt(kPi));
}

// Inverts beckmannSlopeCdf(x, mu) = target on (-inf, mu]: Newton kept inside a bisection bracket.
double invertBeckmannSlopeCdf(double target, double mu) {
  double lo = std::min(mu, 0.0) - 10.0, hi = std::min(mu, 10.0);
  double x = 0.5 * (lo + hi);
  for (int i = 0; i < 100; ++i) {
    const double f = beckmannSlopeCdf(x, mu) - target;
    if (f > 0) hi = x; else lo = x;
    const double slope = (mu - x) * std::exp(-x * x) / std::sqrt(kPi);
    double next = slope > 0 ? x - f / slope : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) < 1e-12 * (1.0 + std::abs(x))) return next;
    x = next;
  }
  return x;
}

// Visible slopes of the alpha = 1 Beckmann surface seen from unit direction (sinT, 0, cosT).
glm::dvec2 sampleBeckmannSlopes(double cosT, double sinT, double u1, double u2) {
  const double y = erfInv(std::clamp(2.0 * u2 - 1.0, -1.0 + 1e-15, 1.0 - 1e-15));
  if (sinT < 1e-9) return {erfInv(std::clamp(2.0 * u1 - 1.0, -1.0 + 1e-15, 1.0 - 1e-15)), y};
  const double mu = cosT / sinT;
  if (mu < -25.0) return {mu, y};  // seen from almost straight below: only the steepest facets
  const double total = beckmannSlopeCdf(mu, mu);
  return {invertBeckmannSlopeCdf(u1 * total, mu), y};
}

// GGX visible normals of the alpha = 1 surface: a uniform point on the spherical cap
// z >= -wh.z, shifted by wh (valid for wh on the whole sphere).
Vec3 sampleGgxStretched(const Vec3& wh, double u1, double u2) {
  const double phi = 2.0 * kPi * u1;
  const double z = (1.0 - u2) * (1.0 + wh.z) - wh.z;
  const double sinT = std::sqrt(std::max(0.0, 1.0 - z * z));
  return Vec3(sinT * std::cos(phi), sinT * std::sin(phi), z) + wh;
}

}  // namespace

double erfInv(double y) {
  // Giles' single-precision approximation, polished by two Newton steps on erf.
  const double w0 = -std::log((1.0 - y) * (1.0 + y));
  double x;
  if (w0 < 5.0) {
    const double w = w0 - 2.5;
    double p = 2.81022636e-08;
    for (double c : {3.43273939e-07, -3.5233877e-06, -4.39150654e-06, 0.00021858087, -0.00125372503,
                     -0.00417768164, 0.246640727, 1.50140941})
      p = p * w + c;
    x = p * y;
  } else {
    const double w = std::sqrt(w0) - 3.0;
    double p = -0.000200214257;
    for (double c : {0.000100950558, 0.00134934322, -0.00367342844, 0.00573950773, -0.0076224613,
                     0.00943887047, 1.00167406, 2.83297682})
      p = p * w + c;
    x = p * y;
  }
  for (int i = 0; i < 2; ++i) {
    const double deriv = 2.0 / std::sqrt(kPi) * std::exp(-x * x);
    if (deriv > 0) x -= (std::erf(x) - y) / deriv;
  }
  return x;
}

double Microsurface::D(const Vec3& m) const {
  if (m.z <= 0) return 0;
  const double sx = m.x / alphaX, sy = m.y / alphaY;  // slopes × cos θ, stretched
  const double z2 = m.z * m.z;
  if (ndf == Ndf::GGX) {
    const double q = sx * sx + sy * sy + z2;
    return 1.0 / (kPi * alphaX * alphaY * q * q);
  }
  return std::exp(-(sx * sx + sy * sy) / z2) / (kPi * alphaX * alphaY * z2 * z2);
}

double Microsurface::lambdaUp(const Vec3& w) const {
  if (w.z == 0) return kInf;
  const double t2 = stretchedTan2(*this, w);
  if (t2 == 0) return 0;
  if (ndf == Ndf::GGX) return t2 / (2.0 * (std::sqrt(1.0 + t2) + 1.0));
  const double a = 1.0 / std::sqrt(t2);  // cot θ / alpha, > 0
  return -0.5 * std::erfc(a) + std::exp(-a * a) / (2.0 * a * std::sqrt(kPi));
}

double Microsurface::lambda(const Vec3& w) const {
  const double up = lambdaUp(w);
  return w.z >= 0 ? up : -1.0 - up;
}

double Microsurface::g1Dist(const Vec3& w) const {
  // Below, 1 + Λ(ω) = -Λ(-ω): written so, it keeps its precision when Λ(-ω) is small.
  const double up = lambdaUp(w);
  return w.z >= 0 ? 1.0 / (1.0 + up) : 1.0 / up;
}

double Microsurface::projectedArea(const Vec3& w) const {
  if (w.z == 0) {  // the limit of |z| Λ as z -> 0: the projected roughness over 2 (GGX), 2 sqrt(pi)
    const double a = std::hypot(alphaX * w.x, alphaY * w.y);
    return ndf == Ndf::GGX ? 0.5 * a : a / (2.0 * std::sqrt(kPi));
  }
  const double up = lambdaUp(w);
  return w.z >= 0 ? w.z * (1.0 + up) : -w.z * up;
}

double Microsurface::visibleNormalPdf(const Vec3& w, const Vec3& m) const {
  const double cosWm = glm::dot(w, m);
  if (cosWm <= 0 || m.z <= 0) return 0;
  const double area = projectedArea(w);
  return area > 0 ? cosWm * D(m) / area : 0;
}

Vec3 Microsurface::sampleVisibleNormal(const Vec3& w, double u1, double u2) const {
  // Stretch to the alpha = 1 configuration, sample there, unstretch the normal.
  const Vec3 wh = glm::normalize(Vec3(alphaX * w.x, alphaY * w.y, w.z));
  if (ndf == Ndf::GGX) {
    const Vec3 h = sampleGgxStretched(wh, u1, u2);
    return glm::normalize(Vec3(alphaX * h.x, alphaY * h.y, std::max(h.z, 1e-300)));
  }
  const double sinT = std::sqrt(wh.x * wh.x + wh.y * wh.y);
  const glm::dvec2 s = sampleBeckmannSlopes(wh.z, sinT, u1, u2);
  const double c = sinT > 1e-9 ? wh.x / sinT : 1.0, n = sinT > 1e-9 ? wh.y / sinT : 0.0;
  const double sx = alphaX * (c * s.x - n * s.y), sy = alphaY * (n * s.x + c * s.y);
  return glm::normalize(Vec3(-sx, -sy, 1.0));
}

}  // namespace penumbra::bsdf
