#include "core/bsdf/bsdf.h"

#include <cmath>

namespace penumbra::bsdf {
namespace {

double indexOn(const WalkParams& p, const Vec3& w) {
  return p.facets == Facets::Dielectric && w.z < 0 ? p.ior : 1.0;
}

}  // namespace

Vec3 MicrofacetBsdf::eval(const Vec3& wo, const Vec3& wi, Rng& rng) const {
  if (wo.z == 0) return Vec3(0.0);
  return estimateExitDensity(p_, wi, wo, rng) / std::abs(wo.z);
}

std::optional<BsdfSample> MicrofacetBsdf::sample(const Vec3& wo, Rng& rng) const {
  const std::optional<WalkExit> exit = sampleWalk(p_, wo, rng);
  if (!exit) return std::nullopt;
  BsdfSample s;
  s.wi = exit->direction;
  s.transmission = (wo.z > 0) != (s.wi.z > 0);
  // The walk carries energy from wo to wi; radiance from wi to wo differs across the interface
  // by (eta_wo / eta_wi)^2 (f(wo, wi) / eta_wo^2 = f(wi, wo) / eta_wi^2).
  const double ratio = indexOn(p_, wo) / indexOn(p_, s.wi);
  s.weight = exit->weight * (ratio * ratio);
  s.pdf = pdf(wo, s.wi);
  s.pdfIsProportional = !p_.singleScattering || p_.facets == Facets::RoughDiffuse;
  return s;
}

double MicrofacetBsdf::pdf(const Vec3& wo, const Vec3& wi) const {
  return firstBounceDensity(p_, wo, wi);
}

}  // namespace penumbra::bsdf
