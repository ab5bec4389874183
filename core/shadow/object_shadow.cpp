#include "core/shadow/object_shadow.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/geom/clip.h"
#include "core/scene/convex_solid.h"
#include "core/shadow/critical_wedge.h"
#include "core/shadow/plane_trace.h"

namespace penumbra {

namespace {

constexpr size_t kMaxElements = 0xffff;  // ElementRef indices are 16 bits

// The plane through three points, or nullopt when they are (nearly) on one line.
std::optional<Plane> planeThrough(const Vec3& a, const Vec3& b, const Vec3& c, double eps) {
  const Vec3 normal = glm::cross(b - a, c - a);
  const double length = glm::length(normal);
  if (!(length > eps * std::max(glm::length(b - a), glm::length(c - a)))) return std::nullopt;
  return Plane::throughPoint(normal / length, a);
}

bool allBehind(const Polygon3& points, const Plane& plane, double eps) {
  return std::all_of(points.begin(), points.end(), [&](const Vec3& p) { return plane.signedDistance(p) <= eps; });
}

// The plane oriented with the solid on its front if it separates the solid from the light.
std::optional<Plane> separating(const Plane& plane, const ConvexSolid& solid, const Polygon3& light, double eps) {
  const int side = solid.side(plane, eps);
  if (side == 0) return std::nullopt;
  const Plane oriented = side > 0 ? plane : plane.flipped();
  if (!allBehind(light, oriented, eps)) return std::nullopt;
  return oriented;
}

// False when p and q lie more than onPlane() on one side (both front or both back) of
// every face plane through vertex v (at least two): v is then on no silhouette seen from
// the edge pq.
bool mayBeSilhouetteVertex(std::span<const Face> faces, const Vec3& v, const Vec3& p, const Vec3& q, const Tolerance& tol) {
  const double eps = tol.length(), onPlane = tol.onPlane();
  int through = 0;
  bool allFront = true, allBack = true;
  for (const Face& face : faces) {
    const Plane& plane = face.plane;
    if (!(std::abs(plane.signedDistance(v)) <= eps)) continue;
    ++through;
    const double dp = plane.signedDistance(p), dq = plane.signedDistance(q);
    allFront = allFront && dp > onPlane && dq > onPlane;
    allBack = allBack && dp < -onPlane && dq < -onPlane;
    if (!allFront && !allBack) return true;
  }
  return through < 2;
}

}  // namespace

bool castsAsOneOccluder(const Scene& scene, size_t light, uint32_t handle, const Face& receiver) {
  const ConvexSolid* solid = scene.convexSolid(handle);
  if (!solid || solid->vertices.size() > kMaxElements || solid->edges.size() > kMaxElements) return false;
  const Plane lightPlane = scene.lights().at(light).plane();
  const double onPlane = scene.tolerance().onPlane();
  return std::all_of(solid->vertices.begin(), solid->vertices.end(), [&](const Vec3& v) {
    return receiver.plane.signedDistance(v) > onPlane && lightPlane.signedDistance(v) > onPlane;
  });
}

FaceId castingOccluder(const Scene& scene, size_t light, FaceId face, const Face& receiver, bool wholeObjects) {
  if (wholeObjects && castsAsOneOccluder(scene, light, face.object, receiver)) return wholeObject(face.object);
  return face;
}

std::optional<SingleShadow> castObjectShadow(const Scene& scene, size_t light, uint32_t handle,
                                             const Face& receiver, const PlaneFrame& frame) {
  const Tolerance tol = scene.tolerance();
  const double eps = tol.length();
  const Polygon3& lightPolygon = scene.lights().at(light).polygon;
  const Plane lightPlane = scene.lights()[light].plane();
  // Light points behind the receiver's plane light none of it.
  const Polygon3 s = withoutFlatCorners(clipFront(lightPolygon, receiver.plane, eps), eps);
  if (s.size() < 3 || area(s) <= tol.area()) return std::nullopt;
  const ConvexSolid* solidOf = scene.convexSolid(handle);
  if (!solidOf || solidOf->vertices.size() < 4) return std::nullopt;
  const ConvexSolid& solid = *solidOf;
  const std::span<const Face> faces = scene.facesOfObject(handle);

  // R ∩ front of the light's plane (it emits forward only).
  Polygon2 outline;
  outline.reserve(receiver.polygon.size());
  for (const Vec3& p : receiver.polygon) outline.push_back(frame.to2D(p));
  const Polygon2 receiver2 = counterClockwise(outline);
  const Polygon2 base = clipFrontOf(receiver2, PlaneTrace::of(lightPlane, frame, tol), eps);
  if (base.size() < 3 || signedArea(base) <= tol.area()) return std::nullopt;

  auto clipBy = [&](Polygon2& region, const Plane& plane) {
    region = clipFrontOf(region, PlaneTrace::of(plane, frame, tol), eps);
    return region.size() >= 3;
  };
  const size_t n = s.size();
  // Per light vertex, the planes through it and an edge of the solid that support the
  // solid (its silhouette edges from there), oriented with the solid on their front.
  struct Support {
    uint32_t edge;
    Plane plane;
  };
  std::vector<std::vector<Support>> supports(n);
  for (size_t i = 0; i < n; ++i)
    for (uint32_t e = 0; e < solid.edges.size(); ++e) {
      const auto plane = planeThrough(s[i], solid.vertices[solid.edges[e].first], solid.vertices[solid.edges[e].second], eps);
      if (!plane) continue;
      if (const int side = solid.side(*plane, eps)) supports[i].push_back({e, side > 0 ? *plane : plane->flipped()});
    }

  // Penumbra: in front of every separating plane (a supporting plane with the light behind).
  Polygon2 penumbra = base;
  bool open = true;
  for (size_t i = 0; i < n && open; ++i) {
    for (const Support& support : supports[i])
      if (allBehind(s, support.plane, eps) && !(open = clipBy(penumbra, support.plane))) break;
    for (const Vec3& v : solid.vertices) {
      if (!open) break;
      const auto plane = planeThrough(s[i], s[(i + 1) % n], v, eps);
      if (const auto cut = plane ? separating(*plane, solid, s, eps) : std::nullopt) open = clipBy(penumbra, *cut);
    }
  }
  if (!open || penumbra.size() < 3 || signedArea(penumbra) <= tol.area()) return std::nullopt;

  // Umbra: inside the cone from every light vertex over the solid, i.e. in front of every
  // supporting plane through it (none if a light vertex lies on the receiver's plane: its
  // cone meets the plane there only).
  auto onReceiver = [&](const Vec3& p) { return std::abs(receiver.plane.signedDistance(p)) <= eps; };
  Polygon2 umbra;
  if (std::none_of(s.begin(), s.end(), onReceiver)) {
    umbra = penumbra;
    bool left = true;
    for (size_t i = 0; i < n && left; ++i)
      for (const Support& support : supports[i])
        if (!(left = clipBy(umbra, support.plane))) break;
    if (!left || umbra.size() < 3 || signedArea(umbra) <= tol.area()) umbra.clear();
  }

  // Segments: the silhouette surfaces cut by the receiver's plane inside base.
  SegmentCollector segments(receiver2, penumbra, umbra, eps);
  auto keepAll = [] { return true; };
  for (size_t i = 0; i < n; ++i) {
    if (onReceiver(s[i])) continue;  // its rays never come back to the receiver
    for (const Support& support : supports[i]) {
      const uint32_t e = support.edge;
      const auto w = vertexEdgeWedge({ElementRef::Kind::Vertex, uint16_t(i)}, {ElementRef::Kind::Edge, uint16_t(e)}, s[i],
                                     solid.vertices[solid.edges[e].first], solid.vertices[solid.edges[e].second], eps);
      if (!w) continue;
      if (const auto chord = wedgeChord(*w, base, frame, tol))
        segments.add(chord->first, chord->second, w->lightElement, w->occluderElement, keepAll);
    }
  }
  for (size_t i = 0; i < n; ++i) {
    const Vec3 &p = s[i], &q = s[(i + 1) % n];
    if (onReceiver(p) && onReceiver(q)) continue;
    for (uint32_t v = 0; v < solid.vertices.size(); ++v) {
      if (!mayBeSilhouetteVertex(faces, solid.vertices[v], p, q, tol)) continue;
      const auto w = edgeVertexWedge({ElementRef::Kind::Edge, uint16_t(i)}, {ElementRef::Kind::Vertex, uint16_t(v)}, p, q,
                                     solid.vertices[v], eps);
      if (!w) continue;
      if (const auto chord = wedgeChord(*w, base, frame, tol))
        segments.add(chord->first, chord->second, w->lightElement, w->occluderElement, keepAll);
    }
  }

  SingleShadow out;
  out.light = uint32_t(light);
  out.occluder = wholeObject(handle);
  out.receiver = receiver.id;
  out.segments = segments.take();
  out.penumbra = std::move(penumbra);
  out.umbra = std::move(umbra);
  return out;
}

}  // namespace penumbra
