// The visible part of one light from one point, given candidate occluder faces:
// the light clipped to the point's front half-space minus the central projections
// of the faces that block the point (SCENE_FORMAT.md rule), as convex pieces, and
// its Lambert integral. Shadows are gathered, then subtracted largest first (so the
// light is gone, or its pieces few, early). One object per (light, point), one thread.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/geom/convex2d.h"
#include "core/geom/plane_frame.h"
#include "core/illum/visible_region.h"
#include "core/mesh/mesh.h"
#include "core/scene/scene.h"

namespace penumbra {

class Backprojection {
 public:
  // Light `light` of `scene` seen from p with unit front normal n, nothing removed yet.
  Backprojection(const Scene& scene, size_t light, const Vec3& p, const Vec3& n);

  // Whether the light faces p (p strictly in front of its plane) and some of it lies
  // in front of p's plane; otherwise it contributes nothing and has no class.
  bool applies() const { return applies_; }

  // Removes the projection of `face` if it can block p: p lies more than onPlane()
  // behind its plane and part of it lies between p and the light, inside the cone
  // from p over the light. Returns whether it was projected (one source/occluder
  // comparison); the subtraction happens when a result is asked for. The result
  // depends on the set of faces given and not on their order.
  bool occlude(const Face& face);

  // The same for the limit as the point tends to p from direction d (unit, in p's
  // plane): a face whose plane contains p blocks iff p + δd is behind it, and then
  // hides the light points q in front of its plane whose segment from p + δd
  // crosses it as δ → 0 (p on the face, q − p entering it). Other faces as occlude().
  bool occludeApproaching(const Face& face, const Vec3& d);

  // ∫ cosθp·cosθL / r² dA over the front part of the light, and over what is left.
  double unoccludedFactor() const;
  double visibleFactor() const;
  // Some candidate removed positive area; some positive area is left.
  bool occluded() const {
    resolve();
    return occluded_;
  }
  bool anyVisible() const;
  // Lit (nothing removed), Umbra (nothing left) or Penumbra; Lit if !applies().
  LightClass lightClass() const;
  size_t comparisons() const { return comparisons_; }
  // The visible part in world space (on the light's plane), convex pieces.
  std::vector<Polygon3> visiblePieces() const;

 private:
  void subtractShadow(const Polygon3& onLightPlane);
  // Subtracts the gathered shadows, the one covering most of the light first.
  void resolve() const;
  bool kept(size_t piece) const;  // a resolved piece of positive area (at area())

  Tolerance tolerance_;
  Vec3 p_{0.0}, n_{0.0};
  Plane lightPlane_;
  double pHeight_ = 0;          // p's distance in front of the light's plane
  bool applies_ = false;
  Polygon3 front_;              // the light clipped to p's front half-space
  PlaneFrame frame_;            // 2D frame on the light's plane
  std::vector<Plane> cone_;     // inward side planes of a cone from p over front_ plus a margin
  Polygon2 front2_;             // front_ in the frame, CCW
  // Resolved state (filled lazily by resolve(); one thread owns the object).
  mutable VisibleRegion visible_;
  mutable std::vector<Vec2> pendingPoints_;   // gathered shadows, flat
  mutable std::vector<uint32_t> pendingStarts_;  // shadow i: [starts[i], starts[i+1])
  mutable bool occluded_ = false;
  mutable Polygon3 blocker_, scratch_;  // reused clipping buffers
  size_t comparisons_ = 0;
};

// One-shot form: the light from p minus the candidate faces (ids not in the scene
// are ignored).
struct LightVisibleFactor {
  bool applies = false;
  double unoccludedFactor = 0;
  double visibleFactor = 0;
  LightClass lightClass = LightClass::Lit;
  size_t comparisons = 0;
};
LightVisibleFactor backproject(const Scene& scene, size_t light, const Vec3& p, const Vec3& n,
                               std::span<const FaceId> candidates);

}  // namespace penumbra
