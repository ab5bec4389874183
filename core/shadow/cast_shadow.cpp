#include "core/shadow/cast_shadow.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <utility>

#include "core/geom/clip.h"
#include "core/shadow/convex_silhouette.h"
#include "core/shadow/plane_trace.h"

namespace penumbra {

namespace {

// Duplicates and vertices within eps of the line through their neighbours go:
// a flat corner would generate EV wedges that are no discontinuity.
Polygon3 simplified(Polygon3 polygon, double eps) {
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

// A critical surface: the cone at `apex` spanned by d1, d2, in `plane`. VE (light
// vertex s, occluder edge ab): apex s, d1 = a − s, d2 = b − s (the part beyond ab
// is the part behind O's plane). EV (light edge pq, occluder vertex v): apex v,
// d1 = v − p, d2 = v − q (rays through v continue behind O's plane).
struct Wedge {
  ElementRef lightElement, occluderElement;
  bool vertexEdge = false;  // VE; else EV
  Vec3 apex{0.0}, d1{0.0}, d2{0.0};
  Plane plane;              // normal d1 × d2
  Vec3 lightPoints[2];      // the generating light vertex (twice) or edge end points
  Vec3 occluderPoints[2];   // the generating occluder edge end points or vertex (twice)
};

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

std::vector<Wedge> allWedges(const CastingPair& pair, double eps) {
  const Polygon3& s = pair.light;
  const Polygon3& o = pair.occluder;
  std::vector<Wedge> wedges;
  wedges.reserve(2 * s.size() * o.size());
  for (size_t i = 0; i < s.size(); ++i)
    for (size_t j = 0; j < o.size(); ++j) {
      const Vec3& a = o[j];
      const Vec3& b = o[(j + 1) % o.size()];
      auto w = makeWedge({ElementRef::Kind::Vertex, uint16_t(i)}, {ElementRef::Kind::Edge, uint16_t(j)},
                         true, s[i], a - s[i], b - s[i], eps);
      if (!w) continue;
      w->lightPoints[0] = w->lightPoints[1] = s[i];
      w->occluderPoints[0] = a;
      w->occluderPoints[1] = b;
      wedges.push_back(*w);
    }
  for (size_t i = 0; i < s.size(); ++i)
    for (size_t j = 0; j < o.size(); ++j) {
      const Vec3& p = s[i];
      const Vec3& q = s[(i + 1) % s.size()];
      auto w = makeWedge({ElementRef::Kind::Edge, uint16_t(i)}, {ElementRef::Kind::Vertex, uint16_t(j)},
                         false, o[j], o[j] - p, o[j] - q, eps);
      if (!w) continue;
      w->lightPoints[0] = p;
      w->lightPoints[1] = q;
      w->occluderPoints[0] = w->occluderPoints[1] = o[j];
      wedges.push_back(*w);
    }
  return wedges;
}

bool allOn(const Plane& plane, std::initializer_list<Vec3> points, double eps) {
  return std::all_of(points.begin(), points.end(),
                     [&](const Vec3& p) { return std::abs(plane.signedDistance(p)) <= eps; });
}

// The wedge's plane oriented with O' on its front if it separates O' from S'.
std::optional<Plane> separatingPlane(const Wedge& w, const CastingPair& pair, double eps) {
  auto sides = [&](const Plane& plane) {
    const bool occluderFront = std::all_of(pair.occluder.begin(), pair.occluder.end(),
                                           [&](const Vec3& p) { return plane.signedDistance(p) >= -eps; });
    const bool lightBack = std::all_of(pair.light.begin(), pair.light.end(),
                                       [&](const Vec3& p) { return plane.signedDistance(p) <= eps; });
    return occluderFront && lightBack;
  };
  if (sides(w.plane)) return w.plane;
  if (sides(w.plane.flipped())) return w.plane.flipped();
  return std::nullopt;
}

// The parameter interval of a→b running along the boundary of a convex polygon
// (collinear with some edges within eps), as the hull over those edges.
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

bool samePoints(const Piece& x, const Piece& y, double eps) {
  auto near = [&](const Vec2& p, const Vec2& q) { return glm::length(p - q) <= eps; };
  return (near(x.a, y.a) && near(x.b, y.b)) || (near(x.a, y.b) && near(x.b, y.a));
}

}  // namespace

std::optional<CastingPair> castingPair(const Scene& scene, size_t light, const Face& occluder,
                                       const Face& receiver) {
  const Tolerance tol = scene.tolerance();
  const double eps = tol.length();
  const Polygon3& lightPolygon = scene.lights().at(light).polygon;
  const auto lightPlane = planeOf(lightPolygon);
  if (!lightPlane) return std::nullopt;
  CastingPair pair;
  pair.light = simplified(
      clipFront(clipFront(lightPolygon, receiver.plane, eps), occluder.plane, eps), eps);
  pair.occluder = simplified(
      clipFront(clipFront(occluder.polygon, receiver.plane, eps), *lightPlane, eps), eps);
  if (pair.light.size() < 3 || area(pair.light) <= tol.area()) return std::nullopt;
  if (pair.occluder.size() < 3 || area(pair.occluder) <= tol.area()) return std::nullopt;
  return pair;
}

std::optional<SingleShadow> castShadow(const Scene& scene, size_t light, const Face& occluder,
                                       const Face& receiver, const PlaneFrame& frame,
                                       bool silhouetteOnly) {
  const Tolerance tol = scene.tolerance();
  const double eps = tol.length();
  const Plane& occluderPlane = occluder.plane;
  const Plane& receiverPlane = receiver.plane;

  // Cheap reject: O shadows only points strictly behind its plane.
  if (std::none_of(receiver.polygon.begin(), receiver.polygon.end(), [&](const Vec3& p) {
        return occluderPlane.signedDistance(p) < -tol.onPlane();
      }))
    return std::nullopt;
  const auto pair = castingPair(scene, light, occluder, receiver);
  if (!pair) return std::nullopt;
  const Plane lightPlane = *planeOf(scene.lights()[light].polygon);

  // R ∩ front of the light's plane (it emits forward only) ∩ behind O's plane.
  Polygon2 base;
  base.reserve(receiver.polygon.size());
  for (const Vec3& p : receiver.polygon) base.push_back(frame.to2D(p));
  const Polygon2 receiver2 = counterClockwise(base);
  base = clipFrontOf(receiver2, PlaneTrace::of(lightPlane, frame, tol), eps);
  base = clipFrontOf(base, PlaneTrace::of(occluderPlane.flipped(), frame, tol), eps);
  if (base.size() < 3 || signedArea(base) <= tol.area()) return std::nullopt;

  const std::vector<Wedge> wedges = allWedges(*pair, eps);
  auto onOccluderPlane = [&](const Vec3& p) { return allOn(occluderPlane, {p}, eps); };

  // Penumbra: behind the separating planes (O' on their front). A plane through a
  // light point on O's plane and an O' element is O's plane itself: already in base.
  Polygon2 penumbra = base;
  for (const Wedge& w : wedges) {
    if (allOn(occluderPlane, {w.lightPoints[0], w.lightPoints[1]}, eps)) continue;
    const auto separating = separatingPlane(w, *pair, eps);
    if (!separating) continue;
    penumbra = clipFrontOf(penumbra, PlaneTrace::of(*separating, frame, tol), eps);
    if (penumbra.size() < 3) break;
  }
  if (penumbra.size() < 3 || signedArea(penumbra) <= tol.area()) return std::nullopt;

  // Umbra: every light vertex hidden, i.e. x on O's side of every VE plane; light
  // points on O's plane are never blocked, so then there is none.
  Polygon2 umbra;
  if (std::none_of(pair->light.begin(), pair->light.end(), onOccluderPlane)) {
    umbra = penumbra;
    for (const Wedge& w : wedges) {
      if (!w.vertexEdge) continue;
      // d1 × d2 = (a − s) × (b − s) points away from O' (O' is CCW about O's normal
      // and s is in front of O's plane).
      umbra = clipFrontOf(umbra, PlaneTrace::of(w.plane.flipped(), frame, tol), eps);
      if (umbra.size() < 3) break;
    }
    if (umbra.size() < 3 || signedArea(umbra) <= tol.area()) umbra.clear();
  }

  SingleShadow out;
  out.light = uint32_t(light);
  out.occluder = occluder.id;
  out.receiver = receiver.id;

  // Segments: each wedge cut by R's plane inside base. A closed convex occluder's
  // surfaces off every silhouette bound no change of the light seen (convex_silhouette.h):
  // their inner pieces are dropped (region edges stay: the face's own regions need them).
  std::optional<ConvexSilhouette> silhouette;
  if (silhouetteOnly && scene.isClosedConvex(occluder.id.object))
    silhouette.emplace(scene.facesOfObject(occluder.id.object), tol);
  std::vector<char> contactDone(pair->occluder.size(), 0);
  std::vector<Piece> pieces;
  std::vector<std::pair<ElementRef, ElementRef>> elements;
  auto onReceiver = [&](const Vec3& p) { return allOn(receiverPlane, {p}, eps); };
  for (const Wedge& w : wedges) {
    const Vec3 &l0 = w.lightPoints[0], &l1 = w.lightPoints[1];
    const Vec3 &o0 = w.occluderPoints[0], &o1 = w.occluderPoints[1];
    bool contact = false;
    if (w.vertexEdge) {
      // Rays from a light vertex on R's plane never come back to it; a light vertex on
      // O's plane (or everything in the light's plane) gives O's (the light's) plane.
      if (onReceiver(l0) || onOccluderPlane(l0) || allOn(lightPlane, {l0, o0, o1}, eps)) continue;
      contact = onReceiver(o0) && onReceiver(o1);
      if (contact && std::exchange(contactDone[w.occluderElement.index], char(1))) continue;
    } else {
      // Rays through an occluder vertex on R's plane meet it only there.
      if (onReceiver(o0) || allOn(occluderPlane, {l0, l1}, eps) || allOn(receiverPlane, {l0, l1}, eps) ||
          allOn(lightPlane, {o0}, eps))
        continue;
    }
    const PlaneTrace trace = PlaneTrace::of(w.plane, frame, tol);
    if (trace.kind != PlaneTrace::Kind::Line) continue;
    // The cone's two bounding half-spaces, each containing the other ray.
    const Vec3 m = w.plane.normal;
    Vec3 n1 = glm::cross(w.d1, m), n2 = glm::cross(w.d2, m);
    if (glm::dot(n1, w.d2) < 0) n1 = -n1;
    if (glm::dot(n2, w.d1) < 0) n2 = -n2;
    Polygon2 region = base;
    region = clipFrontOf(region, PlaneTrace::of(Plane::throughPoint(glm::normalize(n1), w.apex), frame, tol), eps);
    region = clipFrontOf(region, PlaneTrace::of(Plane::throughPoint(glm::normalize(n2), w.apex), frame, tol), eps);
    const auto chord = chordAlong(region, trace, eps, eps);
    if (!chord) continue;

    const Piece whole{chord->a, chord->b, contact ? SegmentKind::Contact : SegmentKind::Internal};
    std::vector<Piece> kept;
    if (contact) {
      kept.push_back(whole);
    } else {
      std::vector<Piece> rest, inner;
      splitAlong(penumbra, whole, SegmentKind::Penumbra, eps, &kept, &rest);
      for (const Piece& piece : rest) splitAlong(umbra, piece, SegmentKind::Umbra, eps, &kept, &inner);
      if (!inner.empty() && (!silhouette || silhouette->mayBeSilhouette({o0, o1}, {l0, l1})))
        kept.insert(kept.end(), inner.begin(), inner.end());
    }
    for (const Piece& piece : kept) {
      // R's own boundary is already in its tree.
      if (alongBoundary(receiver2, piece.a, piece.b, eps)) continue;
      const bool duplicate = std::any_of(pieces.begin(), pieces.end(), [&](const Piece& other) {
        return other.kind == piece.kind && samePoints(other, piece, eps);
      });
      if (duplicate) continue;
      pieces.push_back(piece);
      elements.emplace_back(w.lightElement, w.occluderElement);
    }
  }

  out.penumbra = std::move(penumbra);
  out.umbra = std::move(umbra);
  out.segments.reserve(pieces.size());
  for (size_t i = 0; i < pieces.size(); ++i)
    out.segments.push_back(
        CriticalSegment{pieces[i].a, pieces[i].b, pieces[i].kind, elements[i].first, elements[i].second});
  return out;
}

}  // namespace penumbra
