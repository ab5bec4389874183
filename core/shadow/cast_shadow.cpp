#include "core/shadow/cast_shadow.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <utility>

#include "core/geom/clip.h"
#include "core/shadow/convex_silhouette.h"
#include "core/shadow/critical_wedge.h"
#include "core/shadow/plane_trace.h"

namespace penumbra {

namespace {

std::vector<Wedge> allWedges(const CastingPair& pair, double eps) {
  const Polygon3& s = pair.light;
  const Polygon3& o = pair.occluder;
  std::vector<Wedge> wedges;
  wedges.reserve(2 * s.size() * o.size());
  for (size_t i = 0; i < s.size(); ++i)
    for (size_t j = 0; j < o.size(); ++j)
      if (auto w = vertexEdgeWedge({ElementRef::Kind::Vertex, uint32_t(i)}, {ElementRef::Kind::Edge, uint32_t(j)},
                                   s[i], o[j], o[(j + 1) % o.size()], eps))
        wedges.push_back(*w);
  for (size_t i = 0; i < s.size(); ++i)
    for (size_t j = 0; j < o.size(); ++j)
      if (auto w = edgeVertexWedge({ElementRef::Kind::Edge, uint32_t(i)}, {ElementRef::Kind::Vertex, uint32_t(j)},
                                   s[i], s[(i + 1) % s.size()], o[j], eps))
        wedges.push_back(*w);
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

}  // namespace

bool reachesFrontOf(const Face& occluder, const Face& receiver, const Tolerance& tolerance) {
  const double eps = tolerance.length();
  return std::any_of(occluder.polygon.begin(), occluder.polygon.end(),
                     [&](const Vec3& p) { return receiver.plane.signedDistance(p) > eps; });
}

std::optional<CastingPair> castingPair(const Scene& scene, size_t light, const Face& occluder,
                                       const Face& receiver) {
  const Tolerance tol = scene.tolerance();
  const double eps = tol.length();
  // clipFront keeps a side only where some vertex is beyond eps (convex_split.h).
  if (!reachesFrontOf(occluder, receiver, tol)) return std::nullopt;
  const Polygon3& lightPolygon = scene.lights().at(light).polygon;
  const auto lightPlane = planeOf(lightPolygon);
  if (!lightPlane) return std::nullopt;
  CastingPair pair;
  pair.light = withoutFlatCorners(
      clipFront(clipFront(lightPolygon, receiver.plane, eps), occluder.plane, eps), eps);
  pair.occluder = withoutFlatCorners(
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
  SegmentCollector segments(receiver2, penumbra, umbra, eps);
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
    const auto chord = wedgeChord(w, base, frame, tol);
    if (!chord) continue;
    if (contact)
      segments.addWhole(chord->first, chord->second, SegmentKind::Contact, w.lightElement, w.occluderElement);
    else
      segments.add(chord->first, chord->second, w.lightElement, w.occluderElement,
                   [&] { return !silhouette || silhouette->mayBeSilhouette({o0, o1}, {l0, l1}); });
  }

  out.segments = segments.take();
  out.cullsBehind = !umbra.empty() && std::all_of(occluder.polygon.begin(), occluder.polygon.end(), [&](const Vec3& p) {
    return receiverPlane.signedDistance(p) > tol.onPlane();
  });
  out.penumbra = std::move(penumbra);
  out.umbra = std::move(umbra);
  return out;
}

}  // namespace penumbra
