#include "core/geom/convex2d.h"

#include <algorithm>
#include <cmath>

#include "core/geom/convex_split.h"

namespace penumbra {

namespace {

struct Box2 {
  Vec2 min{INFINITY}, max{-INFINITY};
  explicit Box2(const Polygon2& polygon) {
    for (const Vec2& v : polygon) {
      min = glm::min(min, v);
      max = glm::max(max, v);
    }
  }
  bool apartFrom(const Box2& o, double eps) const {
    return min.x > o.max.x + eps || o.min.x > max.x + eps || min.y > o.max.y + eps ||
           o.min.y > max.y + eps;
  }
};

}  // namespace

Polygon2 withoutDuplicateVertices(const Polygon2& polygon, double eps) {
  Polygon2 out;
  out.reserve(polygon.size());
  for (const Vec2& v : polygon)
    if (out.empty() || glm::length(v - out.back()) > eps) out.push_back(v);
  while (out.size() > 1 && glm::length(out.front() - out.back()) <= eps) out.pop_back();
  return out;
}

double signedArea(std::span<const Vec2> polygon) {
  if (polygon.size() < 3) return 0;
  // Relative to the first vertex: less cancellation far from the origin.
  const Vec2 o = polygon[0];
  double twice = 0;
  for (size_t i = 1; i + 1 < polygon.size(); ++i)
    twice += cross2(polygon[i] - o, polygon[i + 1] - o);
  return 0.5 * twice;
}

Polygon2 counterClockwise(Polygon2 polygon) {
  if (signedArea(polygon) < 0) std::reverse(polygon.begin(), polygon.end());
  return polygon;
}

double lineDistance(const Vec2& a, const Vec2& b, const Vec2& p) {
  const Vec2 d = b - a;
  const double length = glm::length(d);
  return length > 0 ? cross2(d, p - a) / length : 0.0;
}

namespace {
// Splits by the directed line a→b (left = front); a zero-length line splits nothing.
void splitByDirectedLine(const Polygon2& polygon, const Vec2& a, const Vec2& b, double eps,
                         Polygon2* left, Polygon2* right) {
  const Vec2 d = b - a;
  const double length = glm::length(d);
  if (!(length > 0)) return;
  splitConvex(polygon, [&](const Vec2& v) { return cross2(d, v - a) / length; }, eps, left, right);
}
}  // namespace

Polygon2 clipLeftOf(const Polygon2& polygon, const Vec2& a, const Vec2& b, double eps) {
  Polygon2 left;
  splitByDirectedLine(polygon, a, b, eps, &left, nullptr);
  return left;
}

Split2 splitByLine(const Polygon2& polygon, const Vec2& a, const Vec2& b, double eps) {
  Split2 out;
  splitByDirectedLine(polygon, a, b, eps, &out.left, &out.right);
  return out;
}

Polygon2 intersect(const Polygon2& a, const Polygon2& b, double eps) {
  const Polygon2 clipper = withoutDuplicateVertices(b, eps);
  if (clipper.size() < 3 || a.size() < 3) return {};
  Polygon2 rest = a;
  for (size_t i = 0; i < clipper.size() && !rest.empty(); ++i)
    rest = clipLeftOf(rest, clipper[i], clipper[(i + 1) % clipper.size()], eps);
  return rest;
}

std::vector<Polygon2> subtract(const Polygon2& a, const Polygon2& b, double eps, bool* overlapped) {
  if (overlapped) *overlapped = false;
  if (a.size() < 3) return {};
  const Polygon2 cutter = withoutDuplicateVertices(b, eps);
  if (cutter.size() < 3 || Box2(a).apartFrom(Box2(cutter), eps)) return {a};
  // Peel off the part of A outside each edge of B in turn; what stays is A ∩ B.
  std::vector<Polygon2> pieces;
  Polygon2 rest = a;
  for (size_t i = 0; i < cutter.size(); ++i) {
    Split2 s = splitByLine(rest, cutter[i], cutter[(i + 1) % cutter.size()], eps);
    if (s.left.empty()) return {a};  // A ∩ B has no area: leave A whole
    if (!s.right.empty()) pieces.push_back(std::move(s.right));
    rest = std::move(s.left);
  }
  if (overlapped) *overlapped = true;
  return pieces;
}

std::vector<Polygon2> subtract(const Polygon2& a, const std::vector<Polygon2>& bs, double eps,
                               bool* overlapped) {
  if (overlapped) *overlapped = false;
  std::vector<Polygon2> pieces{a};
  std::vector<Polygon2> next;
  for (const Polygon2& b : bs) {
    next.clear();
    for (const Polygon2& piece : pieces) {
      bool cut = false;
      std::vector<Polygon2> rest = subtract(piece, b, eps, &cut);
      if (cut && overlapped) *overlapped = true;
      for (Polygon2& r : rest) next.push_back(std::move(r));
    }
    pieces.swap(next);
    if (pieces.empty()) break;
  }
  return pieces;
}

bool contains(const Polygon2& polygon, const Vec2& p, double eps) {
  if (polygon.size() < 3) return false;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[(i + 1) % polygon.size()];
    if (a == b) continue;
    if (lineDistance(a, b, p) < -eps) return false;
  }
  return true;
}

Vec2 areaCentroid(const Polygon2& polygon) {
  const Vec2 o = polygon[0];
  Vec2 sum{0.0};
  double twice = 0;
  for (size_t i = 1; i + 1 < polygon.size(); ++i) {
    const double w = cross2(polygon[i] - o, polygon[i + 1] - o);
    sum += w * (polygon[i] + polygon[i + 1] - 2.0 * o);
    twice += w;
  }
  return o + sum / (3.0 * twice);
}

}  // namespace penumbra
