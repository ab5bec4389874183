// An oriented plane n·x + d = 0 with unit normal n; "front" is where n points.
// Plain value; thread-safe.
#pragma once

#include "core/geom/vec.h"

namespace penumbra {

enum class Side { Front, Back, On, Spanning };

struct Plane {
  Vec3 normal{0, 0, 1};
  double offset = 0;  // d in n·x + d = 0

  static Plane throughPoint(const Vec3& unitNormal, const Vec3& point) {
    return Plane{unitNormal, -glm::dot(unitNormal, point)};
  }
  double signedDistance(const Vec3& p) const { return glm::dot(normal, p) + offset; }
  Plane flipped() const { return Plane{-normal, -offset}; }
  Vec3 project(const Vec3& p) const { return p - signedDistance(p) * normal; }
};

// Classifies a point against a plane with tolerance eps.
inline Side classify(const Plane& plane, const Vec3& p, double eps) {
  const double d = plane.signedDistance(p);
  return d > eps ? Side::Front : (d < -eps ? Side::Back : Side::On);
}

}  // namespace penumbra
