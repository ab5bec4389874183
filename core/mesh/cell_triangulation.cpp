#include "core/mesh/cell_triangulation.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

uint32_t CellFan::triangleCount(uint32_t n) const {
  if (n < 3) return 0;
  return usesCentre() ? n : n - 2;
}

std::array<uint32_t, 3> CellFan::triangle(uint32_t n, uint32_t k) const {
  if (usesCentre()) return {n, k, (k + 1) % n};
  return {apex, (apex + k + 1) % n, (apex + k + 2) % n};
}

CellFan fanOfConvexCell(const Polygon2& loop, double eps) {
  const uint32_t n = uint32_t(loop.size());
  if (n < 3) return CellFan{};  // no triangles
  // A vertex is a corner if it is not (within eps) on the segment of its neighbours.
  // Tested as needed, not stored: the first apex usually does (no allocation per piece).
  const auto corner = [&](uint32_t i) {
    return std::abs(lineDistance(loop[(i + n - 1) % n], loop[(i + 1) % n], loop[i])) > eps;
  };
  // A fan apex must be a corner whose both neighbours are corners too: then no
  // fan triangle has its three vertices on one side.
  for (uint32_t apex = 0; apex < n; ++apex)
    if (corner(apex) && corner((apex + 1) % n) && corner((apex + n - 1) % n)) return CellFan{apex};
  return CellFan{CellFan::kCentre};
}

Vec2 vertexAverage(const Polygon2& loop) {
  Vec2 middle{0.0};
  for (const Vec2& q : loop) middle += q;
  return middle / double(loop.size());
}

bool narrowerThan(const Polygon2& polygon, double width) {
  double area = 0, longest = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[(i + 1) % polygon.size()];
    area += cross2(a, b);
    longest = std::max(longest, glm::length(b - a));
  }
  return !(std::abs(area) > width * longest);
}

}  // namespace penumbra
