#include "core/geom/clip.h"

#include <algorithm>

#include "core/geom/convex_split.h"

namespace penumbra {

Polygon3 clipFront(const Polygon3& polygon, const Plane& plane, double eps) {
  Polygon3 front;
  splitConvex(polygon, [&](const Vec3& v) { return plane.signedDistance(v); }, eps, &front, nullptr);
  return front;
}

void clipFrontInto(const Polygon3& polygon, const Plane& plane, double eps, Polygon3& out) {
  out.clear();
  splitConvex(polygon, [&](const Vec3& v) { return plane.signedDistance(v); }, eps, &out, nullptr);
}

Split3 splitByPlane(const Polygon3& polygon, const Plane& plane, double eps) {
  Split3 out;
  splitConvex(polygon, [&](const Vec3& v) { return plane.signedDistance(v); }, eps, &out.front,
              &out.back);
  return out;
}

}  // namespace penumbra
