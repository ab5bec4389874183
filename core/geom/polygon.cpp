#include "core/geom/polygon.h"

#include <algorithm>
#include <cmath>

#include "core/geom/tolerance.h"

namespace penumbra {

Vec3 newellVector(const Polygon3& polygon) {
  Vec3 n{0.0};
  const size_t count = polygon.size();
  for (size_t i = 0; i < count; ++i) {
    n += glm::cross(polygon[i], polygon[(i + 1) % count]);
  }
  return n;
}

double area(const Polygon3& polygon) { return 0.5 * glm::length(newellVector(polygon)); }

Vec3 centroid(const Polygon3& polygon) {
  Vec3 sum{0.0};
  for (const Vec3& v : polygon) sum += v;
  return polygon.empty() ? sum : sum / double(polygon.size());
}

double extent(const Polygon3& polygon) {
  double best = 0;
  for (size_t i = 0; i < polygon.size(); ++i)
    for (size_t j = i + 1; j < polygon.size(); ++j)
      best = std::max(best, glm::length(polygon[i] - polygon[j]));
  return best;
}

std::optional<Plane> planeOf(const Polygon3& polygon) {
  if (polygon.size() < 3) return std::nullopt;
  const Vec3 n = newellVector(polygon);
  const double size = extent(polygon);
  // Twice the area against the squared size: a sliver thinner than 1e-9 of its
  // length has no reliable plane.
  if (!(glm::length(n) > 1e-9 * size * size)) return std::nullopt;
  return Plane::throughPoint(glm::normalize(n), centroid(polygon));
}

double planarityError(const Polygon3& polygon) {
  const auto plane = planeOf(polygon);
  if (!plane) return INFINITY;
  double worst = 0;
  for (const Vec3& v : polygon) worst = std::max(worst, std::abs(plane->signedDistance(v)));
  return worst / extent(polygon);
}

double width(const Polygon3& polygon) {
  const double size = extent(polygon);
  return size > 0 ? 2 * area(polygon) / size : 0;
}

Polygon3 projectedOnto(const Polygon3& polygon, const Plane& plane) {
  Polygon3 out;
  out.reserve(polygon.size());
  for (const Vec3& v : polygon) out.push_back(plane.project(v));
  return out;
}

bool isConvex(const Polygon3& polygon) {
  const auto plane = planeOf(polygon);
  if (!plane) return false;
  const Vec3 n = plane->normal;
  const size_t count = polygon.size();
  const double size = extent(polygon);
  // Every corner turns left (or goes straight) about n, and the turns add up
  // to one full revolution (no star-shaped self-overlap).
  double turning = 0;
  for (size_t i = 0; i < count; ++i) {
    const Vec3 a = polygon[(i + count - 1) % count];
    const Vec3 b = polygon[i];
    const Vec3 c = polygon[(i + 1) % count];
    const Vec3 e0 = b - a, e1 = c - b;
    const double l0 = glm::length(e0), l1 = glm::length(e1);
    if (l0 <= 1e-12 * size || l1 <= 1e-12 * size) return false;  // repeated vertex
    const double sinTurn = glm::dot(glm::cross(e0, e1), n) / (l0 * l1);
    const double cosTurn = glm::dot(e0, e1) / (l0 * l1);
    if (sinTurn < -kRelativePlanarity) return false;
    turning += std::atan2(sinTurn, cosTurn);
  }
  return std::abs(turning - 2 * M_PI) < 1e-6;
}

Polygon3 withoutDuplicateVertices(const Polygon3& polygon, double eps) {
  Polygon3 out;
  for (const Vec3& v : polygon) {
    if (out.empty() || glm::length(v - out.back()) > eps) out.push_back(v);
  }
  while (out.size() > 1 && glm::length(out.front() - out.back()) <= eps) out.pop_back();
  return out;
}

}  // namespace penumbra
