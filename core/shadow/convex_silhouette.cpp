#include "core/shadow/convex_silhouette.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

bool ConvexSilhouette::mayBeSilhouette(std::initializer_list<Vec3> occluderPoints,
                                       std::initializer_list<Vec3> lightPoints) const {
  // Generous on both sides: counting a face that does not pass through the element
  // only adds a condition, and a light point near a plane keeps the surface.
  const double margin = tolerance_.onPlane();
  int through = 0;
  for (const Face& face : faces_) {
    const bool passes = std::all_of(occluderPoints.begin(), occluderPoints.end(), [&](const Vec3& v) {
      return std::abs(face.plane.signedDistance(v)) <= margin;
    });
    if (!passes) continue;
    ++through;
    const bool allFront = std::all_of(lightPoints.begin(), lightPoints.end(), [&](const Vec3& s) {
      return face.plane.signedDistance(s) > margin;
    });
    if (!allFront) return true;
  }
  return through < 2;
}

}  // namespace penumbra
