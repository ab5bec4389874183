#include "core/geom/shaft.h"

#include <cmath>

namespace penumbra {

namespace {

// The plane through x, y, z facing every corner of a and b, if they all lie within eps of its
// inner side; the caller keeps it then.
void keepIfSupporting(const Vec3& x, const Vec3& y, const Vec3& z, const Polygon3& a, const Polygon3& b, double eps,
                      std::vector<Plane>& sides) {
  const Vec3 cross = glm::cross(y - x, z - x);
  const double length = glm::length(cross);
  if (!(length > 0)) return;
  const Plane plane = Plane::throughPoint(cross / length, x);
  bool front = true, back = true;  // every corner within eps of that side
  for (const Polygon3* polygon : {&a, &b})
    for (const Vec3& v : *polygon) {
      const double d = plane.signedDistance(v);
      front = front && d >= -eps;
      back = back && d <= eps;
    }
  if (front == back) return;  // corners on both sides, or all within eps of it (flat: no side)
  sides.push_back(front ? plane : plane.flipped());
}

}  // namespace

Shaft shaftBetween(const Polygon3& a, const Polygon3& b, double eps) {
  Shaft shaft;
  if (a.size() < 3 || b.size() < 3) return shaft;
  // Each polygon's own plane, through three of its corners spread around it.
  for (const Polygon3* polygon : {&a, &b}) {
    const size_t n = polygon->size();
    keepIfSupporting((*polygon)[0], (*polygon)[n / 3], (*polygon)[2 * n / 3], a, b, eps, shaft.sides);
  }
  // An edge of one and a corner of the other.
  for (const auto& [edges, corners] : {std::pair{&a, &b}, std::pair{&b, &a}})
    for (size_t i = 0; i < edges->size(); ++i)
      for (const Vec3& corner : *corners)
        keepIfSupporting((*edges)[i], (*edges)[(i + 1) % edges->size()], corner, a, b, eps, shaft.sides);
  return shaft;
}

}  // namespace penumbra
