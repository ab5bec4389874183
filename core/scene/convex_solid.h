// A closed convex object's faces as one solid: its distinct corners, which corners each
// face uses, and its edges. Made once when the object enters the scene or moves (Scene
// keeps one per closed convex object), read by casting it whole (core/shadow/
// object_shadow.h) and by backprojecting it (core/illum/backprojection.h). Immutable.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "core/geom/plane.h"
#include "core/scene/scene.h"

namespace penumbra {

struct ConvexSolid {
  // Distinct world positions of the faces' corners (faces of one object share corners
  // exactly: one transform of the same authored vertices), sorted lexicographically.
  std::vector<Vec3> vertices;
  // Face f's corners as indices into vertices: corners[faceStarts[f] .. faceStarts[f + 1]).
  std::vector<uint32_t> corners;
  std::vector<uint32_t> faceStarts;
  std::vector<std::pair<uint32_t, uint32_t>> edges;  // distinct, first < second

  // From the object's world faces (Scene::facesOfObject order).
  static ConvexSolid of(std::span<const Face> faces);

  // +1 if every vertex is at or in front of the plane (within eps), −1 if every one is at
  // or behind it, 0 if the plane cuts the solid.
  int side(const Plane& plane, double eps) const;
};

}  // namespace penumbra
