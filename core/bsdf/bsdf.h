// A microfacet BSDF (rough diffuse, rough conductor, rough dielectric) with multiple bounces by
// the position-free walk, in the local frame (+z = macro normal). Immutable; thread-safe given one Rng per thread.
#pragma once

#include <optional>

#include "core/bsdf/walk.h"

namespace penumbra::bsdf {

// Contract (pbrt-v4's BSDF, Mitsuba 3's): wo points to the viewer, wi to the light, both away
// from the surface. Radiance leaving along wo is ∫ f(wo, wi) L(wi) |cos wi| dwi.
struct BsdfSample {
  Vec3 wi;
  Vec3 weight;          // f(wo, wi) |cos wi| / pdf
  double pdf = 0;       // density of wi per unit solid angle (see pdfIsProportional)
  bool pdfIsProportional = false;  // multiple scattering: pdf() is an approximation, for MIS only
  bool transmission = false;
};

class MicrofacetBsdf {
 public:
  explicit MicrofacetBsdf(WalkParams params) : p_(params) {}
  const WalkParams& params() const { return p_; }

  // f(wo, wi) (no cosine). Multiple scattering: a one-walk unbiased estimate, traced from wi.
  Vec3 eval(const Vec3& wo, const Vec3& wi, Rng& rng) const;
  // Samples wi by a walk traced from wo: the adjoint direction, the same BSDF because both height
  // models are reciprocal (f(wo, wi) / η_wo² = f(wi, wo) / η_wi²; tests Reciprocity, SampleEval).
  std::optional<BsdfSample> sample(const Vec3& wo, Rng& rng) const;
  // Exact for single scattering of conductors and dielectrics; otherwise the normalised
  // first-bounce density (integrates to 1; proportional only).
  double pdf(const Vec3& wo, const Vec3& wi) const;

 private:
  WalkParams p_;
};

}  // namespace penumbra::bsdf
