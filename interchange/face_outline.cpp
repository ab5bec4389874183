#include "interchange/face_outline.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace penumbra::interchange {

namespace {

struct Point2 {
  double x, y;
  int index;
};

double cross(const Point2& o, const Point2& a, const Point2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Andrew's monotone chain, counter-clockwise, exactly collinear points left out.
std::vector<Point2> hull(std::vector<Point2> points) {
  std::sort(points.begin(), points.end(), [](const Point2& a, const Point2& b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  if (points.size() < 3) return points;
  std::vector<Point2> out(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {  // lower chain
    while (k >= 2 && cross(out[k - 2], out[k - 1], points[i]) <= 0) --k;
    out[k++] = points[i];
  }
  for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && cross(out[k - 2], out[k - 1], points[i]) <= 0) --k;
    out[k++] = points[i];
  }
  out.resize(k - 1);
  return out;
}

}  // namespace

IndexPolygon convexOutline(const std::vector<Vec3>& positions,
                           const std::vector<IndexPolygon>& triangles, double eps) {
  Vec3 normal(0.0);
  std::set<int> corners;
  for (const IndexPolygon& t : triangles) {
    const Vec3 &a = positions[size_t(t[0])], &b = positions[size_t(t[1])],
               &c = positions[size_t(t[2])];
    normal += glm::cross(b - a, c - a);
    corners.insert(t.begin(), t.end());
  }
  if (!(glm::length(normal) > 0)) return {};
  // (u, v, normal) right-handed: counter-clockwise in (u, v) is counter-clockwise about the normal.
  const Vec3 n = glm::normalize(normal);
  const Vec3 u = glm::normalize(std::abs(n.x) < 0.9 ? glm::cross(n, Vec3(1, 0, 0))
                                                    : glm::cross(n, Vec3(0, 1, 0)));
  const Vec3 v = glm::cross(n, u);
  std::vector<Point2> points;
  for (int i : corners)
    points.push_back({glm::dot(positions[size_t(i)], u), glm::dot(positions[size_t(i)], v), i});
  std::vector<Point2> outline = hull(points);
  // Drop corners that lie on the edge between their neighbours (within eps), until none do.
  for (bool dropped = true; dropped && outline.size() > 3;) {
    dropped = false;
    for (size_t i = 0; i < outline.size() && outline.size() > 3;) {
      const Point2& prev = outline[(i + outline.size() - 1) % outline.size()];
      const Point2& next = outline[(i + 1) % outline.size()];
      const double chord = std::hypot(next.x - prev.x, next.y - prev.y);
      if (std::abs(cross(prev, next, outline[i])) <= eps * chord) {
        outline.erase(outline.begin() + long(i));
        dropped = true;
      } else {
        ++i;
      }
    }
  }
  if (outline.size() < 3) return {};
  IndexPolygon out;
  for (const Point2& p : outline) out.push_back(p.index);
  return out;
}

std::optional<std::vector<IndexPolygon>> facesFromTriangles(
    const std::vector<Vec3>& positions, const std::vector<IndexPolygon>& triangles,
    const std::vector<double>& faceOf) {
  std::map<double, std::vector<IndexPolygon>> trianglesOf;
  double largest = 0;
  for (const IndexPolygon& t : triangles) {
    const double face = faceOf[size_t(t[0])];
    if (faceOf[size_t(t[1])] != face || faceOf[size_t(t[2])] != face) return std::nullopt;
    trianglesOf[face].push_back(t);
    for (int i : t)
      for (int c = 0; c < 3; ++c) largest = std::max(largest, std::abs(positions[size_t(i)][c]));
  }
  // float32 holds a coordinate within half an ulp; corners on an edge move off it by about that.
  const double eps = 4 * std::ldexp(largest, -23);
  std::vector<IndexPolygon> faces;
  for (const auto& [face, tiles] : trianglesOf)
    if (IndexPolygon outline = convexOutline(positions, tiles, eps); !outline.empty())
      faces.push_back(std::move(outline));
  return faces;
}

}  // namespace penumbra::interchange
