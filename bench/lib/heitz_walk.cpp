#include "bench/lib/heitz_walk.h"

#include <cmath>
#include <numbers>

namespace penumbra::bench {
namespace {

using V = glm::dvec3;
constexpr double kPi = std::numbers::pi;

double rnd(std::mt19937_64& g) { return std::uniform_real_distribution<double>(0.0, 1.0)(g); }

// Smith Λ, analytically continued below the horizon: GGX by the sign of z on the square root,
// Beckmann by Λ(-w) = -1 - Λ(w).
double lambdaOf(const HeitzSurface& s, const V& w) {
  const double q = (s.alphaX * s.alphaX * w.x * w.x + s.alphaY * s.alphaY * w.y * w.y) / (w.z * w.z);
  if (s.ndf == HeitzSurface::Ndf::GGX) return 0.5 * (-1.0 + std::copysign(std::sqrt(1.0 + q), w.z));
  if (q == 0) return w.z > 0 ? 0.0 : -1.0;
  const double a = 1.0 / std::sqrt(q);  // cot θ over the projected roughness
  const double up = 0.5 * (std::erf(a) - 1.0) + std::exp(-a * a) / (2.0 * a * std::sqrt(kPi));
  return w.z > 0 ? up : -1.0 - up;
}

// Visible GGX normals by Heitz 2018's warped disk (projected hemisphere), any side of w.
V sampleVisibleGgx(const V& vh, std::mt19937_64& g) {
  const double len2 = vh.x * vh.x + vh.y * vh.y;
  const V t1 = len2 > 0 ? V(-vh.y, vh.x, 0) / std::sqrt(len2) : V(1, 0, 0);
  const V t2 = glm::cross(vh, t1);
  const double r = std::sqrt(rnd(g)), phi = 2 * kPi * rnd(g);
  const double p1 = r * std::cos(phi);
  const double half = 0.5 * (1.0 + vh.z);
  const double p2 = (1.0 - half) * std::sqrt(std::max(0.0, 1.0 - p1 * p1)) + half * r * std::sin(phi);
  return p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
}

// A standard normal deviate by Box-Muller.
double gaussian(std::mt19937_64& g) {
  return std::sqrt(-2.0 * std::log(1.0 - rnd(g))) * std::cos(2 * kPi * rnd(g));
}

// The slope x along the view azimuth of the alpha = 1 Beckmann surface seen from cot θ = mu:
// density ∝ (mu - x)^+ exp(-x²). Far below (mu < -1) t = mu - x has density ∝ t exp(2 mu t - t²):
// a Gamma(2, -2 mu) proposal accepted with exp(-t²). Otherwise the CDF
// mu sqrt(π)/2 erfc(-x) + exp(-x²)/2 inverted by bisection.
double beckmannSlope(double mu, std::mt19937_64& g) {
  if (mu < -1.0) {
    for (;;) {
      const double t = -(std::log(1.0 - rnd(g)) + std::log(1.0 - rnd(g))) / (-2.0 * mu);
      if (rnd(g) < std::exp(-t * t)) return mu - t;
    }
  }
  const auto cdf = [mu](double x) { return 0.5 * mu * std::sqrt(kPi) * std::erfc(-x) + 0.5 * std::exp(-x * x); };
  double lo = -12.0, hi = std::min(mu, 12.0);
  const double target = rnd(g) * cdf(hi);
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (lo + hi);
    (cdf(mid) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Visible Beckmann normals of the alpha = 1 surface seen from unit vh, any side: slopes along and
// across the azimuth, the normal (-slope, 1) normalised.
V sampleVisibleBeckmann(const V& vh, std::mt19937_64& g) {
  const double sinT = std::sqrt(vh.x * vh.x + vh.y * vh.y);
  const double y = gaussian(g) / std::sqrt(2.0);
  if (sinT < 1e-9) return glm::normalize(V(-gaussian(g) / std::sqrt(2.0), -y, 1.0));
  const double x = beckmannSlope(vh.z / sinT, g);
  const double c = vh.x / sinT, s = vh.y / sinT;
  return glm::normalize(V(-(c * x - s * y), -(s * x + c * y), 1.0));
}

// Visible normals of w, any side of the macrosurface: stretched to alpha = 1 and back.
V sampleVisible(const HeitzSurface& s, const V& w, std::mt19937_64& g) {
  const V vh = glm::normalize(V(s.alphaX * w.x, s.alphaY * w.y, w.z));
  const V nh = s.ndf == HeitzSurface::Ndf::GGX ? sampleVisibleGgx(vh, g) : sampleVisibleBeckmann(vh, g);
  return glm::normalize(V(s.alphaX * nh.x, s.alphaY * nh.y, std::max(1e-12, nh.z)));
}

double fresnel(double c, double eta) {  // eta = n_transmitted / n_incident
  const double g2 = eta * eta - 1.0 + c * c;
  if (g2 < 0) return 1.0;
  const double g = std::sqrt(g2);
  const double a = (g - c) / (g + c), b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
  return 0.5 * a * a * (1.0 + b * b);
}

// One height step for a ray at normalized height x = C1(h) in (0, 1] travelling along d:
// the next intersection's x, or a value > 1 when the ray leaves through the top.
double nextHeight(const HeitzSurface& s, const V& d, double x, std::mt19937_64& g) {
  const double u = 1.0 - rnd(g);  // (0, 1]
  if (d.z > 0) {  // P(pass x') = (x / x')^Λ
    const double l = lambdaOf(s, d);
    return l <= 0 ? 2.0 : x * std::pow(u, -1.0 / l);
  }
  return x * std::pow(u, 1.0 / (-lambdaOf(s, d)));  // -Λ(d) = 1 + Λ(-d) going down
}

V cosineAround(const V& n, std::mt19937_64& g) {
  const V a = std::abs(n.x) > 0.5 ? V(0, 1, 0) : V(1, 0, 0);
  const V t = glm::normalize(glm::cross(a, n)), b = glm::cross(n, t);
  const double r = std::sqrt(rnd(g)), phi = 2 * kPi * rnd(g);
  return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1 - r * r)) * n);
}

}  // namespace

std::optional<HeitzExit> heitzWalk(const HeitzSurface& s, const V& wi, std::mt19937_64& g) {
  // State in the frame of the side the ray is on (mirrored through the origin inside, where
  // heights flip too: x -> 1 - x): travelling direction d and height x.
  int side = wi.z > 0 ? 1 : -1;
  if (side < 0 && s.kind != HeitzSurface::Kind::Dielectric) return std::nullopt;
  V d = -double(side) * wi;
  double x = 1.0;  // enters from the top
  for (int bounce = 0; bounce <= s.maxBounces; ++bounce) {
    x = nextHeight(s, d, x, g);
    if (x > 1.0) return HeitzExit{double(side) * d, bounce};
    const V back = -d;
    const V m = sampleVisible(s, back, g);
    if (s.kind == HeitzSurface::Kind::Conductor) {
      d = 2.0 * glm::dot(back, m) * m - back;
    } else if (s.kind == HeitzSurface::Kind::Diffuse) {
      d = cosineAround(m, g);
    } else {
      const double etaI = side > 0 ? 1.0 : s.ior, etaT = side > 0 ? s.ior : 1.0;
      const double c = glm::dot(back, m);
      if (rnd(g) < fresnel(c, etaT / etaI)) {
        d = 2.0 * c * m - back;
      } else {
        const double e = etaI / etaT;
        const double ct = std::sqrt(std::max(0.0, 1.0 - e * e * (1.0 - c * c)));
        const V t = glm::normalize(e * -back + (e * c - ct) * m);
        side = -side;  // now seen from the other side: mirrored direction and height
        d = -t;
        x = 1.0 - x;
      }
    }
  }
  return std::nullopt;
}

}  // namespace penumbra::bench
