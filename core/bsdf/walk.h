// The multiple-bounce random walk of seed 004 over microfacet bounces. Uncorrelated: escapes by
// G1 (eq. 3), no heights. Correlated: the next vertex's height rides along as a distribution
// (vertex_height.h), sampled only in part, so the walk's law is that of Heitz et al. 2016's walk
// with explicit heights. Pure functions; thread-safe given one Rng per thread.
#pragma once

#include <optional>
#include <vector>

#include "core/bsdf/microsurface.h"
#include "core/bsdf/rng.h"
#include "core/bsdf/shadowing.h"

namespace penumbra::bsdf {

enum class Facets { RoughDiffuse, Conductor, Dielectric };

struct WalkParams {
  Microsurface surface;
  Facets facets = Facets::Conductor;
  HeightModel height = HeightModel::Correlated;
  bool singleScattering = false;  // stop after the first bounce (energy of later ones is lost)
  Vec3 albedo{1.0};               // rough diffuse: the Lambertian albedo of each facet
  Vec3 eta{1.0}, k{0.0};          // conductor: complex index relative to the outside
  bool unitFresnel = false;       // conductor with F = 1 (white furnace)
  double ior = 1.5;               // dielectric: index inside (below the macrosurface) / outside
  int maxBounces = 256;
};

// A walk's exit: direction (unit, world frame: +z = macro normal; below = transmitted),
// throughput (Fresnel / albedo products) and the number of bounces.
struct WalkExit {
  Vec3 direction;
  Vec3 weight;
  int bounces = 0;
};

// Traces light arriving from wi (pointing away from the surface) until it escapes. Nothing
// when it is lost (bounce limit; single scattering: in expectation, the weight carries the
// escape probability instead). The exit direction's density times the expected weight is
// f(wi -> wo) |cos wo|.
std::optional<WalkExit> sampleWalk(const WalkParams& p, const Vec3& wi, Rng& rng);

// Unbiased estimate of f(wi -> wo) |cos wo| (the exit density per unit solid angle, weighted),
// by next-event estimation at every bounce. perBounce, when given, receives the contribution of
// each bounce order (index 0: first bounce).
Vec3 estimateExitDensity(const WalkParams& p, const Vec3& wi, const Vec3& wo, Rng& rng,
                         std::vector<Vec3>* perBounce = nullptr);

// The normalised density of the first bounce's scattered direction from wi (escape ignored):
// integrates to 1 over the sphere (exactly for conductors and dielectrics; for rough diffuse,
// the cosine lobe of the macro normal, an approximation).
double firstBounceDensity(const WalkParams& p, const Vec3& wi, const Vec3& wo);

}  // namespace penumbra::bsdf
