// Helpers shared by the overlap tests: seeded sampling on convex polygons and an
// exact segment-blocking predicate independent of Embree and of core/overlap.
// Free functions; thread-safe.
#pragma once

#include <algorithm>
#include <random>
#include <vector>

#include "core/geom/polygon.h"
#include "core/scene/scene.h"

namespace penumbra::overlap_test {

// A point uniformly distributed over the area of a convex polygon (fan triangles
// weighted by area).
inline Vec3 samplePolygon(const Polygon3& polygon, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<double> weights;
  for (size_t k = 1; k + 1 < polygon.size(); ++k)
    weights.push_back(0.5 * glm::length(glm::cross(polygon[k] - polygon[0], polygon[k + 1] - polygon[0])));
  std::discrete_distribution<size_t> pick(weights.begin(), weights.end());
  const size_t k = 1 + pick(rng);
  double a = unit(rng), b = unit(rng);
  if (a + b > 1) a = 1 - a, b = 1 - b;
  return polygon[0] + a * (polygon[k] - polygon[0]) + b * (polygon[k + 1] - polygon[0]);
}

// SCENE_FORMAT.md's rule evaluated directly in double: the segment p→q is
// blocked by `face` iff q is strictly in front of its plane, its plane does not
// contain p, and the segment meets the (closed) polygon. Closed edges make it
// slightly generous, which only makes the cube tests stricter.
inline bool blocksExactly(const Face& face, const Vec3& p, const Vec3& q, double onPlane) {
  const double dq = face.plane.signedDistance(q);
  const double dp = face.plane.signedDistance(p);
  if (dq <= onPlane || std::abs(dp) <= onPlane || dp > 0) return false;
  const Vec3 hit = q + (p - q) * (dq / (dq - dp));
  const Polygon3& poly = face.polygon;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec3& a = poly[i];
    const Vec3& b = poly[(i + 1) % poly.size()];
    if (glm::dot(glm::cross(b - a, hit - a), face.plane.normal) < 0) return false;
  }
  return true;
}

}  // namespace penumbra::overlap_test
