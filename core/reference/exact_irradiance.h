// Brute-force exact direct irradiance at a point: every light, clipped to the
// point's front half-space, minus the central projections of all faces that can
// block it, integrated with Lambert's polygon formula. Shares no code path with
// the DM engine beyond core/geom. Immutable after construction; thread-safe.
#pragma once

#include <vector>

#include "core/geom/polygon.h"
#include "core/mesh/mesh.h"
#include "core/scene/scene.h"

namespace penumbra {

// One light's contribution at a point.
struct LightVisibility {
  // ∫ cosθp·cosθL / r² dA over the part of the light in front of the point
  // (no occlusion) and over the part the point actually sees.
  double unoccludedFactor = 0;
  double visibleFactor = 0;
  LightClass lightClass = LightClass::Lit;
  // The visible part of the light as convex pieces (world space, on its plane).
  std::vector<Polygon3> visiblePieces;
};

struct PointIrradiance {
  Vec3 irradiance{0.0};  // RGB, W·m⁻²
  LightClass lightClass = LightClass::Lit;
};

class ExactReference {
 public:
  explicit ExactReference(const Scene& scene);

  // p lies on a receiving face with unit front normal n. With `shading` (a smooth face's
  // interpolated normal, in front of n's plane), the factors are Lambert's about it over
  // each visible piece clipped to its front; visibility and pieces stay n's.
  PointIrradiance evaluate(const Vec3& p, const Vec3& n) const;
  PointIrradiance evaluate(const Vec3& p, const Vec3& n, const Vec3& shading) const;
  LightVisibility visibility(const Vec3& p, const Vec3& n, size_t light) const;
  LightVisibility visibility(const Vec3& p, const Vec3& n, const Vec3& shading, size_t light) const;

 private:
  const Scene& scene_;
};

// Lambert's exact formula: ∫ cosθp·cosθL / r² dA over a planar polygon seen
// from p with unit normal n (the polygon must lie in front of p's plane).
// Equals π × the point-to-polygon form factor.
double lambertFactor(const Vec3& p, const Vec3& n, const Polygon3& polygon);

}  // namespace penumbra
