#include "core/scene/convex_solid.h"

#include <algorithm>

namespace penumbra {

namespace {

bool lexicographic(const Vec3& a, const Vec3& b) {
  return a.x < b.x || (a.x == b.x && (a.y < b.y || (a.y == b.y && a.z < b.z)));
}

}  // namespace

ConvexSolid ConvexSolid::of(std::span<const Face> faces) {
  ConvexSolid solid;
  for (const Face& face : faces) solid.vertices.insert(solid.vertices.end(), face.polygon.begin(), face.polygon.end());
  std::sort(solid.vertices.begin(), solid.vertices.end(), lexicographic);
  solid.vertices.erase(std::unique(solid.vertices.begin(), solid.vertices.end()), solid.vertices.end());
  solid.faceStarts.push_back(0);
  for (const Face& face : faces) {
    for (const Vec3& p : face.polygon)
      solid.corners.push_back(
          uint32_t(std::lower_bound(solid.vertices.begin(), solid.vertices.end(), p, lexicographic) - solid.vertices.begin()));
    solid.faceStarts.push_back(uint32_t(solid.corners.size()));
  }
  for (size_t f = 0; f + 1 < solid.faceStarts.size(); ++f) {
    const uint32_t begin = solid.faceStarts[f], end = solid.faceStarts[f + 1];
    for (uint32_t k = begin; k < end; ++k) {
      const uint32_t a = solid.corners[k], b = solid.corners[k + 1 < end ? k + 1 : begin];
      if (a != b) solid.edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(solid.edges.begin(), solid.edges.end());
  solid.edges.erase(std::unique(solid.edges.begin(), solid.edges.end()), solid.edges.end());
  return solid;
}

int ConvexSolid::side(const Plane& plane, double eps) const {
  bool front = true, back = true;
  for (const Vec3& v : vertices) {
    const double d = plane.signedDistance(v);
    front = front && d >= -eps;
    back = back && d <= eps;
    if (!front && !back) return 0;
  }
  return front ? 1 : -1;
}

}  // namespace penumbra
