#include "core/bsdf/walk.h"

#include <cmath>
#include <numbers>

#include "core/bsdf/fresnel.h"
#include "core/bsdf/vertex_height.h"

namespace penumbra::bsdf {
namespace {

// The walk's state: the side of the interface the ray is on (+1 outside, -1 inside a
// dielectric) and, in that side's frame (world mirrored through the origin for -1, so +z
// points into the ray's medium), the direction the light arrived from at the next vertex, and
// (height-correlated model) that vertex's height as a distribution.
struct State {
  int side = 1;
  Vec3 w;
  Vec3 beta{1.0};
  VertexHeight height;
};

double indexOf(const WalkParams& p, int side) { return side > 0 ? 1.0 : p.ior; }

// A cosine-distributed direction about unit n (Lambertian facet).
Vec3 sampleCosineAbout(const Vec3& n, double u1, double u2) {
  const double sign = std::copysign(1.0, n.z);  // Duff et al.'s branchless orthonormal basis
  const double a = -1.0 / (sign + n.z), b = n.x * n.y * a;
  const Vec3 t(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
  const Vec3 s(b, sign + n.y * n.y * a, -n.y);
  const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
  return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * s + std::sqrt(std::max(0.0, 1.0 - u1)) * n);
}

struct Scattered {
  Vec3 d;     // in the frame of `side`
  int side;
  Vec3 weight;
};

// Scatters the light arriving from w on the microfacet with normal m.
Scattered scatter(const WalkParams& p, const State& s, const Vec3& m, Rng& rng) {
  switch (p.facets) {
    case Facets::RoughDiffuse: {
      const double u1 = rng.uniform(), u2 = rng.uniform();
      return {sampleCosineAbout(m, u1, u2), s.side, p.albedo};
    }
    case Facets::Conductor: {
      const Vec3 f = p.unitFresnel ? Vec3(1.0) : fresnelConductor(glm::dot(s.w, m), p.eta, p.k);
      return {reflect(s.w, m), s.side, f};
    }
    case Facets::Dielectric: break;
  }
  const double eta = indexOf(p, -s.side) / indexOf(p, s.side);
  const double f = fresnelDielectric(glm::dot(s.w, m), eta);
  if (rng.uniform() < f) return {reflect(s.w, m), s.side, Vec3(1.0)};
  const std::optional<Vec3> t = refract(s.w, m, eta);
  if (!t) return {reflect(s.w, m), s.side, Vec3(1.0)};  // f == 1 already; rounding only
  return {-*t, -s.side, Vec3(1.0)};
}

// Probability that a ray leaving the vertex of s along d escapes; d in the frame of the side it
// leaves into (across: the other one, after refraction).
double escapeProbability(const WalkParams& p, const State& s, const Vec3& d, bool across, Rng& rng) {
  if (d.z <= 0) return 0;
  if (p.height == HeightModel::Uncorrelated) return p.surface.g1Dist(d);
  const double lambda = p.surface.lambdaUp(d);
  return across ? escapeAcross(s.height, lambda, rng) : escapeAway(s.height, lambda);
}

// Follows the scattered ray: true when it escapes; otherwise s becomes the next vertex's state.
// Correlated: the escape and the next height are drawn from the vertex's height distribution,
// so the heights of successive vertices stay correlated as on a real microsurface.
bool escapes(const WalkParams& p, State& s, const Scattered& sc, Rng& rng) {
  VertexHeight h = s.height;
  if (p.height == HeightModel::Uncorrelated) {
    if (rng.uniform() < escapeProbability(p, s, sc.d, sc.side != s.side, rng)) return true;
  } else {
    if (sc.side != s.side) h = crossed(h, rng);
    const double lambda = p.surface.lambdaUp(sc.d);
    if (sc.d.z > 0) {
      if (rng.uniform() < escapeAway(h, lambda)) return true;
      h = blockedAway(h, lambda, rng);
    } else {
      h = intoSurface(h, 1.0 + lambda, rng);
    }
  }
  s = State{sc.side, -sc.d, s.beta * sc.weight, h};
  return false;
}

// Density of the mirror direction o about visible normals from w, per unit solid angle of o;
// cosWh receives w·h for the Fresnel factor.
double reflectDensity(const Microsurface& ms, const Vec3& w, const Vec3& o, double& cosWh) {
  const Vec3 sum = w + o;
  if (glm::dot(sum, sum) == 0) return 0;
  const Vec3 h = glm::normalize(sum);
  cosWh = glm::dot(w, h);
  return cosWh > 0 ? ms.visibleNormalPdf(w, h) / (4.0 * cosWh) : 0.0;
}

// Density of the refracted direction t (pointing into the other medium) about visible normals
// from w (Walter et al. 2007's Jacobian); cosWh receives w·h.
double refractDensity(const Microsurface& ms, const Vec3& w, const Vec3& t, double etaI, double etaT,
                      double& cosWh) {
  Vec3 h = -(etaI * w + etaT * t);
  if (glm::dot(h, h) == 0) return 0;
  h = glm::normalize(h);
  if (h.z < 0) h = -h;
  cosWh = glm::dot(w, h);
  const double cosTh = glm::dot(t, h);
  if (cosWh <= 0 || cosTh >= 0) return 0;
  const double denom = etaI * cosWh + etaT * cosTh;
  return ms.visibleNormalPdf(w, h) * etaT * etaT * -cosTh / (denom * denom);
}

// Density of leaving at this vertex along world direction wo, times the escape probability.
// m: the sampled visible normal, used only by diffuse facets (a one-sample estimate).
Vec3 exitDensity(const WalkParams& p, const State& s, const Vec3& m, const Vec3& wo, Rng& rng) {
  const Microsurface& ms = p.surface;
  const Vec3 o = double(s.side) * wo;  // wo in this side's frame
  if (o.z > 0) {                       // leaving by reflection
    const double esc = escapeProbability(p, s, o, false, rng);
    if (esc <= 0) return Vec3(0.0);
    if (p.facets == Facets::RoughDiffuse) return p.albedo * (std::max(0.0, glm::dot(o, m)) / kPi * esc);
    double cosWh = 0;
    const double density = reflectDensity(ms, s.w, o, cosWh);
    if (!(density > 0)) return Vec3(0.0);
    if (p.facets == Facets::Conductor) {
      const Vec3 f = p.unitFresnel ? Vec3(1.0) : fresnelConductor(cosWh, p.eta, p.k);
      return f * (density * esc);
    }
    const double f = fresnelDielectric(cosWh, indexOf(p, -s.side) / indexOf(p, s.side));
    return Vec3(f * density * esc);
  }
  if (p.facets != Facets::Dielectric || o.z == 0) return Vec3(0.0);
  // Leaving by refraction: o points into the other medium; -o is its direction in that side's frame.
  const double esc = escapeProbability(p, s, -o, true, rng);
  if (esc <= 0) return Vec3(0.0);
  const double etaI = indexOf(p, s.side), etaT = indexOf(p, -s.side);
  double cosWh = 0;
  const double density = refractDensity(ms, s.w, o, etaI, etaT, cosWh);
  if (!(density > 0)) return Vec3(0.0);
  return Vec3((1.0 - fresnelDielectric(cosWh, etaT / etaI)) * density * esc);
}

// The first state of a walk for light arriving from wi; nothing when wi cannot be lit.
std::optional<State> start(const WalkParams& p, const Vec3& wi) {
  // The first hit's height: rate 1 / G1 of wi seen from its own side (the same for ±wi).
  const VertexHeight h = firstVertex(1.0 + p.surface.lambdaUp(wi));
  if (wi.z > 0) return State{1, wi, Vec3(1.0), h};
  if (wi.z < 0 && p.facets == Facets::Dielectric) return State{-1, -wi, Vec3(1.0), h};
  return std::nullopt;
}

}  // namespace

std::optional<WalkExit> sampleWalk(const WalkParams& p, const Vec3& wi, Rng& rng) {
  std::optional<State> s = start(p, wi);
  if (!s) return std::nullopt;
  for (int bounce = 1; bounce <= p.maxBounces; ++bounce) {
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const Vec3 m = p.surface.sampleVisibleNormal(s->w, u1, u2);
    const Scattered sc = scatter(p, *s, m, rng);
    const Vec3 beta = s->beta * sc.weight;
    if (p.singleScattering) {
      const double esc = escapeProbability(p, *s, sc.d, sc.side != s->side, rng);
      if (esc <= 0) return std::nullopt;
      return WalkExit{double(sc.side) * sc.d, beta * esc, 1};
    }
    if (escapes(p, *s, sc, rng)) return WalkExit{double(sc.side) * sc.d, beta, bounce};
  }
  return std::nullopt;
}

Vec3 estimateExitDensity(const WalkParams& p, const Vec3& wi, const Vec3& wo, Rng& rng,
                         std::vector<Vec3>* perBounce) {
  if (perBounce) perBounce->clear();
  Vec3 total(0.0);
  std::optional<State> s = start(p, wi);
  if (!s) return total;
  for (int bounce = 1; bounce <= p.maxBounces; ++bounce) {
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const Vec3 m = p.surface.sampleVisibleNormal(s->w, u1, u2);
    const Vec3 c = s->beta * exitDensity(p, *s, m, wo, rng);
    total += c;
    if (perBounce) perBounce->push_back(c);
    if (p.singleScattering) break;
    const Scattered sc = scatter(p, *s, m, rng);
    if (escapes(p, *s, sc, rng)) break;
  }
  return total;
}

double firstBounceDensity(const WalkParams& p, const Vec3& wi, const Vec3& wo) {
  std::optional<State> s = start(p, wi);
  if (!s) return 0;
  if (p.facets == Facets::RoughDiffuse) return wo.z > 0 ? wo.z / kPi : 0.0;
  const Vec3 o = double(s->side) * wo;
  double cosWh = 0;
  const double reflected = reflectDensity(p.surface, s->w, o, cosWh);
  if (p.facets == Facets::Conductor) return reflected;
  const double etaI = indexOf(p, s->side), etaT = indexOf(p, -s->side);
  double total = reflected > 0 ? reflected * fresnelDielectric(cosWh, etaT / etaI) : 0.0;
  if (o.z < 0) {
    const double refracted = refractDensity(p.surface, s->w, o, etaI, etaT, cosWh);
    if (refracted > 0) total += refracted * (1.0 - fresnelDielectric(cosWh, etaT / etaI));
  }
  return total;
}

}  // namespace penumbra::bsdf
