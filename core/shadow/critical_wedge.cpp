#include "core/shadow/critical_wedge.h"

#include <algorithm>
#include <cmath>

#include "core/geom/clip.h"
#include "core/shadow/plane_trace.h"

namespace penumbra {

namespace {

std::optional<Wedge> makeWedge(ElementRef lightElement, ElementRef occluderElement, bool vertexEdge,
                               const Vec3& apex, const Vec3& d1, const Vec3& d2, double eps) {
  const Vec3 normal = glm::cross(d1, d2);
  const double length = glm::length(normal);
  // |d1 × d2| = |edge| · distance of the apex from the edge's line.
  if (!(length > eps * glm::length(d1 - d2))) return std::nullopt;
  Wedge w;
  w.lightElement = lightElement;
  w.occluderElement = occluderElement;
  w.vertexEdge = vertexEdge;
  w.apex = apex;
  w.d1 = d1;
  w.d2 = d2;
  w.plane = Plane::throughPoint(normal / length, apex);
  return w;
}

struct Piece {
  Vec2 a, b;
  SegmentKind kind;
};

// Splits a→b into the part along `polygon`'s boundary (kind `on`) and the rest
// (kind `off`); pieces no longer than eps are dropped.
void splitAlong(const Polygon2& polygon, const Piece& piece, SegmentKind on, double eps,
                std::vector<Piece>* onPieces, std::vector<Piece>* offPieces) {
  const auto interval = polygon.size() >= 3 ? alongBoundary(polygon, piece.a, piece.b, eps)
                                             : std::nullopt;
  if (!interval) {
    offPieces->push_back(piece);
    return;
  }
  const Vec2 d = piece.b - piece.a;
  const double length = glm::length(d);
  auto at = [&](double t) { return t <= 0 ? piece.a : (t >= 1 ? piece.b : piece.a + t * d); };
  auto emit = [&](double t0, double t1, SegmentKind kind, std::vector<Piece>* out) {
    if ((t1 - t0) * length > eps) out->push_back(Piece{at(t0), at(t1), kind});
  };
  emit(0, interval->first, piece.kind, offPieces);
  emit(interval->first, interval->second, on, onPieces);
  emit(interval->second, 1, piece.kind, offPieces);
}

bool samePoints(const CriticalSegment& x, const CriticalSegment& y, double eps) {
  auto near = [&](const Vec2& p, const Vec2& q) { return glm::length(p - q) <= eps; };
  return (near(x.a, y.a) && near(x.b, y.b)) || (near(x.a, y.b) && near(x.b, y.a));
}

}  // namespace

// Duplicates and vertices within eps of the line through their neighbours go:
// a flat corner would generate EV wedges that are no discontinuity.
Polygon3 withoutFlatCorners(Polygon3 polygon, double eps) {
  polygon = withoutDuplicateVertices(polygon, eps);
  for (bool changed = true; changed && polygon.size() >= 3;) {
    changed = false;
    const size_t n = polygon.size();
    for (size_t i = 0; i < n; ++i) {
      const Vec3& p = polygon[(i + n - 1) % n];
      const Vec3& r = polygon[(i + 1) % n];
      const Vec3 d = r - p;
      const double length = glm::length(d);
      if (length <= eps || glm::length(glm::cross(d, polygon[i] - p)) <= eps * length) {
        polygon.erase(polygon.begin() + long(i));
        changed = true;
        break;
      }
    }
  }
  return polygon.size() >= 3 ? polygon : Polygon3{};
}

std::optional<Wedge> vertexEdgeWedge(ElementRef lightVertex, ElementRef occluderEdge, const Vec3& s,
                                     const Vec3& a, const Vec3& b, double eps) {
  auto w = makeWedge(lightVertex, occluderEdge, true, s, a - s, b - s, eps);
  if (!w) return std::nullopt;
  w->lightPoints[0] = w->lightPoints[1] = s;
  w->occluderPoints[0] = a;
  w->occluderPoints[1] = b;
  return w;
}

std::optional<Wedge> edgeVertexWedge(ElementRef lightEdge, ElementRef occluderVertex, const Vec3& p,
                                     const Vec3& q, const Vec3& v, double eps) {
  auto w = makeWedge(lightEdge, occluderVertex, false, v, v - p, v - q, eps);
  if (!w) return std::nullopt;
  w->lightPoints[0] = p;
  w->lightPoints[1] = q;
  w->occluderPoints[0] = w->occluderPoints[1] = v;
  return w;
}

std::optional<std::pair<Vec2, Vec2>> wedgeChord(const Wedge& w, const Polygon2& base,
                                                const PlaneFrame& frame, const Tolerance& tolerance) {
  const double eps = tolerance.length();
  const PlaneTrace trace = PlaneTrace::of(w.plane, frame, tolerance);
  if (trace.kind != PlaneTrace::Kind::Line) return std::nullopt;
  // The cone's two bounding half-spaces, each containing the other ray.
  const Vec3 m = w.plane.normal;
  Vec3 n1 = glm::cross(w.d1, m), n2 = glm::cross(w.d2, m);
  if (glm::dot(n1, w.d2) < 0) n1 = -n1;
  if (glm::dot(n2, w.d1) < 0) n2 = -n2;
  Polygon2 region = base;
  region = clipFrontOf(region, PlaneTrace::of(Plane::throughPoint(glm::normalize(n1), w.apex), frame, tolerance), eps);
  region = clipFrontOf(region, PlaneTrace::of(Plane::throughPoint(glm::normalize(n2), w.apex), frame, tolerance), eps);
  const auto chord = chordAlong(region, trace, eps, eps);
  if (!chord) return std::nullopt;
  return std::pair{chord->a, chord->b};
}

bool wedgePlaneMisses(const Wedge& w, const Polygon3& polygon, double eps) {
  return wedgePlaneMisses(w.apex, w.d1, w.d2, polygon, eps);
}

bool wedgePlaneMisses(const Vec3& apex, const Vec3& d1, const Vec3& d2, const Polygon3& polygon, double eps) {
  const Vec3 normal = glm::cross(d1, d2);
  const double length = glm::length(normal);
  if (!(length > 0)) return false;  // no plane: makeWedge refuses it
  bool allFront = !polygon.empty(), allBack = allFront;
  for (const Vec3& p : polygon) {
    const double d = glm::dot(normal, p - apex) / length;
    allFront = allFront && d > 2 * eps;
    allBack = allBack && d < -2 * eps;
    if (!allFront && !allBack) return false;
  }
  return allFront || allBack;
}

std::optional<std::pair<double, double>> alongBoundary(const Polygon2& polygon, const Vec2& a,
                                                       const Vec2& b, double eps) {
  const Vec2 d = b - a;
  const double length2 = glm::dot(d, d);
  const double segmentLength = std::sqrt(length2);
  bool any = false;
  double t0 = 1, t1 = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec2& p = polygon[i];
    const Vec2& q = polygon[(i + 1) % polygon.size()];
    // Judge collinearity against the longer of the two lines (the better-conditioned one).
    const bool collinear =
        segmentLength >= glm::length(q - p)
            ? std::abs(lineDistance(a, b, p)) <= eps && std::abs(lineDistance(a, b, q)) <= eps
            : std::abs(lineDistance(p, q, a)) <= eps && std::abs(lineDistance(p, q, b)) <= eps;
    if (!collinear) continue;
    const double tp = glm::dot(p - a, d) / length2, tq = glm::dot(q - a, d) / length2;
    const double lo = std::max(0.0, std::min(tp, tq)), hi = std::min(1.0, std::max(tp, tq));
    if ((hi - lo) * segmentLength <= eps) continue;
    t0 = std::min(t0, lo);
    t1 = std::max(t1, hi);
    any = true;
  }
  if (!any) return std::nullopt;
  return std::pair{t0, t1};
}

void SegmentCollector::add(const Vec2& a, const Vec2& b, ElementRef lightElement,
                           ElementRef occluderElement, const std::function<bool()>& keepInner) {
  const Piece whole{a, b, SegmentKind::Internal};
  std::vector<Piece> kept, rest, inner;
  splitAlong(penumbra_, whole, SegmentKind::Penumbra, eps_, &kept, &rest);
  for (const Piece& piece : rest) splitAlong(umbra_, piece, SegmentKind::Umbra, eps_, &kept, &inner);
  if (!inner.empty() && keepInner()) kept.insert(kept.end(), inner.begin(), inner.end());
  for (const Piece& piece : kept) keep(CriticalSegment{piece.a, piece.b, piece.kind, lightElement, occluderElement});
}

void SegmentCollector::addWhole(const Vec2& a, const Vec2& b, SegmentKind kind, ElementRef lightElement,
                                ElementRef occluderElement) {
  keep(CriticalSegment{a, b, kind, lightElement, occluderElement});
}

void SegmentCollector::keep(const CriticalSegment& segment) {
  if (alongBoundary(receiver_, segment.a, segment.b, eps_)) return;
  if (keptAlready(segment)) return;
  segments_.push_back(segment);
  if (segments_.size() == kIndexFrom)
    for (uint32_t i = 0; i < segments_.size(); ++i) index(i);
  else if (segments_.size() > kIndexFrom)
    index(uint32_t(segments_.size() - 1));
}

bool SegmentCollector::keptAlready(const CriticalSegment& segment) const {
  auto same = [&](const CriticalSegment& other) {
    return other.kind == segment.kind && samePoints(other, segment, eps_);
  };
  if (segments_.size() < kIndexFrom) return std::any_of(segments_.begin(), segments_.end(), same);
  // A segment with the same ends has one within eps of segment.a: in a cell next to a's.
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy) {
      const auto it = byCell_.find(cellKey(segment.a, dx, dy));
      if (it == byCell_.end()) continue;
      for (const uint32_t i : it->second)
        if (same(segments_[i])) return true;
    }
  return false;
}

uint64_t SegmentCollector::cellKey(const Vec2& p, int dx, int dy) const {
  // Far-off coordinates share the outermost cells: more candidates, never a missed one.
  auto cell = [&](double x, int d) {
    double c = std::floor(x / (2 * eps_));
    if (!(c > -2e9)) c = -2e9;  // NaN too
    if (!(c < 2e9)) c = 2e9;
    return uint32_t(int32_t(c) + d);
  };
  return uint64_t(cell(p.x, dx)) << 32 | cell(p.y, dy);
}

void SegmentCollector::index(uint32_t segment) {
  const CriticalSegment& s = segments_[segment];
  byCell_[cellKey(s.a, 0, 0)].push_back(segment);
  const uint64_t b = cellKey(s.b, 0, 0);
  if (b != cellKey(s.a, 0, 0)) byCell_[b].push_back(segment);
}

}  // namespace penumbra
