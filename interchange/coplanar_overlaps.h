// Faces of an import that lie in one plane and overlap in a region of positive
// area (not merely touching along an edge), facing the same way or back to back.
// Scene assembly drops a face lying wholly within another that faces the same way
// and reports every other overlap (README "Import"). Free functions; thread-safe.
#pragma once

#include <compare>
#include <map>
#include <optional>
#include <vector>

#include "core/geom/polygon.h"
#include "core/geom/tolerance.h"

namespace penumbra::interchange {

// A face of the import: its group and its index among the group's faces.
struct FaceRef {
  size_t group = 0, face = 0;
  auto operator<=>(const FaceRef&) const = default;
};

struct CoplanarOverlap {
  FaceRef a, b;  // a < b
  bool backToBack =
      false;        // facing opposite ways: a contact (a box on a floor) or a two-sided sheet
  double area = 0;  // of the overlap, in the plane
  // Facing the same way, one wholly within the other (to within minFaceWidth()): that one;
  // b when each lies within the other.
  std::optional<FaceRef> covered;
};

// `groups[g][f]` is face f of group g: convex, planar, counter-clockwise about its front
// normal. Two faces are coplanar when every corner of each lies within
// tolerance.onPlane() of the other's plane (the distance at which the engine takes a
// point to be in a face's plane), and overlap when their intersection in that plane is
// wider than tolerance.minFaceWidth() (a thinner sliver is two faces meeting along an
// edge, to rounding). A face and its exact reverse in one group are a two-sided surface
// (already counted as such) and are not listed. Sorted by (a, b).
std::vector<CoplanarOverlap> findCoplanarOverlaps(const std::vector<std::vector<Polygon3>>& groups,
                                                  const Tolerance& tolerance);

// The policy: every covered face is dropped (covered → a face covering it, one that
// stays when there is one); the overlaps between faces that stay are kept and reported.
struct CoplanarDecision {
  std::map<FaceRef, FaceRef> dropped;
  std::vector<CoplanarOverlap> kept;
};
CoplanarDecision decideCoplanarOverlaps(const std::vector<CoplanarOverlap>& overlaps);

}  // namespace penumbra::interchange
