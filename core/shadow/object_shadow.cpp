#include "core/shadow/object_shadow.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <utility>
#include <vector>

#include "core/geom/clip.h"
#include "core/geom/shaft.h"
#include "core/util/stamped_set.h"
#include "core/scene/convex_solid.h"
#include "core/scene/mesh_topology.h"
#include "core/shadow/critical_wedge.h"
#include "core/shadow/mesh_silhouette.h"
#include "core/shadow/plane_trace.h"

namespace penumbra {

namespace {

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
  const MeshTopology* mesh = solid ? nullptr : scene.meshTopology(handle);
  if (mesh) solid = &mesh->box;
  if (!solid) return false;
  const Plane lightPlane = scene.lights().at(light).plane();
  const double onPlane = scene.tolerance().onPlane();
  if (mesh) {
    // A mesh on one of its own faces (self-shadowing): the part in front of the face's plane.
    if (receiver.id.object == handle)
      return receiver.id.face < mesh->facesSomethingAhead.size() && mesh->facesSomethingAhead[receiver.id.face] &&
             castsWholeOnItself(scene, light, handle);
    // On another receiver it may touch or pierce the plane (a model resting on the floor):
    // the part in front casts, with contact lines where it meets the plane.
    return castsWholeOnItself(scene, light, handle) &&
           std::any_of(solid->vertices.begin(), solid->vertices.end(),
                       [&](const Vec3& v) { return receiver.plane.signedDistance(v) > onPlane; });
  }
  return std::all_of(solid->vertices.begin(), solid->vertices.end(), [&](const Vec3& v) {
    return receiver.plane.signedDistance(v) > onPlane && lightPlane.signedDistance(v) > onPlane;
  });
}

bool castsWholeOnItself(const Scene& scene, size_t light, uint32_t handle) {
  const MeshTopology* mesh = scene.convexSolid(handle) ? nullptr : scene.meshTopology(handle);
  if (!mesh) return false;
  const Plane lightPlane = scene.lights().at(light).plane();
  const double onPlane = scene.tolerance().onPlane();
  return std::all_of(mesh->box.vertices.begin(), mesh->box.vertices.end(),
                     [&](const Vec3& v) { return lightPlane.signedDistance(v) > onPlane; });
}

FaceId castingOccluder(const Scene& scene, size_t light, FaceId face, const Face& receiver, bool wholeObjects) {
  if (wholeObjects && castsAsOneOccluder(scene, light, face.object, receiver)) return wholeObject(face.object);
  return face;
}

namespace {

// A plane through a light vertex and an edge of the solid that supports the solid (the
// edge is on its silhouette from there), oriented with the solid on its front.
struct Support {
  uint32_t edge;
  Plane plane;
};

// Per light vertex of `s`, its supporting planes.
std::vector<std::vector<Support>> supportsOf(const Polygon3& s, const ConvexSolid& solid, double eps) {
  std::vector<std::vector<Support>> supports(s.size());
  for (size_t i = 0; i < s.size(); ++i)
    for (uint32_t e = 0; e < solid.edges.size(); ++e) {
      const auto plane = planeThrough(s[i], solid.vertices[solid.edges[e].first], solid.vertices[solid.edges[e].second], eps);
      if (!plane) continue;
      if (const int side = solid.side(*plane, eps)) supports[i].push_back({e, side > 0 ? *plane : plane->flipped()});
    }
  return supports;
}

// The receiver's region (in `frame`) as it is clipped by planes, each keeping its front.
class RegionClipper {
 public:
  RegionClipper(const PlaneFrame& frame, const Tolerance& tolerance) : frame_(frame), tolerance_(tolerance) {}
  bool clip(Polygon2& region, const Plane& plane) const {
    region = clipFrontOf(region, PlaneTrace::of(plane, frame_, tolerance_), tolerance_.length());
    return region.size() >= 3 && signedArea(region) > tolerance_.area();
  }

 private:
  const PlaneFrame& frame_;
  Tolerance tolerance_;
};

// In front of every separating plane: the supporting planes with the light behind, and
// the planes through a light edge and a vertex that separate the two. Empty: no shadow.
Polygon2 penumbraRegion(const Polygon2& base, const Polygon3& s, const ConvexSolid& solid,
                        const std::vector<std::vector<Support>>& supports, const RegionClipper& clipper, double eps) {
  Polygon2 penumbra = base;
  for (size_t i = 0; i < s.size(); ++i) {
    for (const Support& support : supports[i])
      if (allBehind(s, support.plane, eps) && !clipper.clip(penumbra, support.plane)) return {};
    for (const Vec3& v : solid.vertices) {
      const auto plane = planeThrough(s[i], s[(i + 1) % s.size()], v, eps);
      if (const auto cut = plane ? separating(*plane, solid, s, eps) : std::nullopt)
        if (!clipper.clip(penumbra, *cut)) return {};
    }
  }
  return penumbra;
}

// Inside the cone from every light vertex over the solid: in front of every supporting
// plane. Empty: no umbra.
Polygon2 umbraRegion(const Polygon2& penumbra, const std::vector<std::vector<Support>>& supports,
                     const RegionClipper& clipper) {
  Polygon2 umbra = penumbra;
  for (const std::vector<Support>& ofVertex : supports)
    for (const Support& support : ofVertex)
      if (!clipper.clip(umbra, support.plane)) return {};
  return umbra;
}

// The faces (indices into the mesh's faces, ascending) of the clusters whose ball comes within
// `reach` of the box around `polygon`.
void nearFaces(const MeshTopology& mesh, const Polygon3& polygon, double reach, std::vector<uint32_t>& out) {
  Vec3 low(INFINITY), high(-INFINITY);
  for (const Vec3& p : polygon) low = glm::min(low, p), high = glm::max(high, p);
  out.clear();
  const auto away = [&](const MeshTopology::Cluster& ball) {
    const Vec3 outside = glm::max(low - ball.centre, glm::max(ball.centre - high, Vec3(0.0)));
    const double within = ball.radius + reach;
    return glm::dot(outside, outside) > within * within;
  };
  mesh.forEachClusterMeeting(away, [&](uint32_t c) {
    const MeshTopology::Cluster& cluster = mesh.clusters[c];
    out.insert(out.end(), mesh.clusterFaces.begin() + cluster.first, mesh.clusterFaces.begin() + cluster.last);
    return true;
  });
  std::sort(out.begin(), out.end());
}

// D0 contact lines: where a face reaching more than onPlane in front of the receiver's
// plane (distances `ahead` of the welded corners) meets it, the edges of its front part
// within onPlane of the plane (a face edge on the plane, or the face cut by it). Each goes out as the VE wedge
// of the first light vertex off the plane over that edge, whose chord is the edge itself
// (as castShadow emits a face's contact edges). Faces lying in the plane cast nothing.
// Only faces near the receiver are looked at (nearFaces): on a model's own faces the plane cuts
// the model along its whole section, and a pass over every face for each face was quadratic.
template <class OnReceiver, class AddContact>
void addContactLines(const Polygon3& s, std::span<const Face> faces, const MeshTopology& mesh,
                     const Face& receiverFace, const OnReceiver& onReceiver,
                     const Tolerance& tol, double contactReach, AddContact&& add) {
  const Plane& receiver = receiverFace.plane;
  const double eps = tol.length(), onPlane = tol.onPlane();
  const auto light = std::find_if_not(s.begin(), s.end(), onReceiver);
  if (light == s.end()) return;
  const ElementRef lightVertex{ElementRef::Kind::Vertex, uint32_t(light - s.begin())};
  const ConvexSolid& w = mesh.welded;
  thread_local Polygon3 front;
  thread_local std::vector<uint32_t> near;
  nearFaces(mesh, receiverFace.polygon, contactReach * tol.sceneSize, near);
  for (const uint32_t f : near) {
    bool anyAhead = false, anyTouching = false;
    for (uint32_t k = w.faceStarts[f]; k < w.faceStarts[f + 1]; ++k) {
      const double ahead = receiver.signedDistance(w.vertices[w.corners[k]]);
      anyAhead = anyAhead || ahead > onPlane;
      anyTouching = anyTouching || !(ahead > onPlane);
    }
    if (!anyAhead || !anyTouching) continue;
    clipFrontInto(faces[f].polygon, receiver, eps, front);
    for (size_t k = 0; k < front.size(); ++k) {
      const Vec3 &a = front[k], &b = front[(k + 1) % front.size()];
      if (!(std::abs(receiver.signedDistance(a)) <= onPlane && std::abs(receiver.signedDistance(b)) <= onPlane))
        continue;
      const uint32_t edge = mesh.cornerEdge[w.faceStarts[f]];  // a label only: the face's first edge
      add(vertexEdgeWedge(lightVertex, {ElementRef::Kind::Edge, uint32_t(edge == MeshTopology::kNoEdge ? 0 : edge)},
                          *light, a, b, eps),
          true);
    }
  }
}

// Well outside the shaft: by this many length tolerances (shaftBetween keeps sides within one).
constexpr double kShaftMargin = 64;

// The clusters whose ball meets the shaft between light part s and the receiver (more than
// kShaftMargin length tolerances outside it, a ball is left out). A VE wedge from s_i over an
// edge reaches the receiver at s_i + t (x − s_i), t ≥ 1, x on the edge, and an EV wedge at
// q + t (v − q) with q on an edge of s: such a point at distance δ outside a side of the shaft
// (s_i, q inside it) has x or v more than δ outside it, so an edge or corner more than the
// margin outside gives no chord on the receiver. Valid until the next call on this thread.
ClusterSet clustersInShaft(const MeshTopology& mesh, const Polygon3& s, const Polygon3& receiver, double eps) {
  thread_local StampedSet inShaft;
  thread_local std::vector<uint32_t> list;
  inShaft.clear(mesh.clusters.size());
  const Shaft shaft = shaftBetween(s, receiver, eps);
  const double margin = kShaftMargin * eps;
  list.clear();
  mesh.forEachClusterMeeting(
      [&](const MeshTopology::Cluster& ball) { return shaft.ballOutside(ball.centre, ball.radius, margin); },
      [&](uint32_t c) {
        inShaft.insert(c);
        list.push_back(c);
        return true;
      });
  return {inShaft.stamps(mesh.clusters.size()), inShaft.stamp(), list};
}

// The VE and EV surfaces of a mesh's potential silhouette (object_shadow.h, any mesh): VE
// (light vertex i, edge e) unless e is regular and off the silhouette from s_i; EV (light
// edge pq, corner v) over the stretch of pq from which v may be on the silhouette
// (silhouetteStretch; all of pq for a corner that is not regular).
template <class OnReceiver, class Add>
void meshSilhouetteWedges(const Polygon3& s, const Polygon3& whole, std::span<const Face> faces, const MeshTopology& mesh,
                          const Face& receiverFace, const OnReceiver& onReceiver, const Tolerance& tol,
                          double contactReach, Add&& add) {
  const Plane& receiver = receiverFace.plane;
  const double eps = tol.length(), onPlane = tol.onPlane();
  const bool wholeLight = s.size() == whole.size() && std::equal(s.begin(), s.end(), whole.begin());
  const ConvexSolid& w = mesh.welded;
  const size_t n = s.size();
  const ClusterSet near = std::isinf(contactReach) ? ClusterSet{} : clustersInShaft(mesh, s, receiverFace.polygon, eps);
  // Only what lies in front of the receiver's plane can shadow it (a mesh on its own face
  // reaches behind it): an edge is cut there, a corner not in front is left out. The distances
  // are read only for the edges and corners in `near`, each on a face of a cluster in it, so
  // only those clusters' corners are found (a pass over every corner per face was quadratic).
  thread_local std::vector<double> ahead;
  ahead.resize(w.vertices.size());
  if (near.stamps.empty())
    for (size_t v = 0; v < w.vertices.size(); ++v) ahead[v] = receiver.signedDistance(w.vertices[v]);
  for (const uint32_t c : near.list)
    for (uint32_t i = mesh.clusters[c].first; i < mesh.clusters[c].last; ++i)
      for (uint32_t k = w.faceStarts[mesh.clusterFaces[i]]; k < w.faceStarts[mesh.clusterFaces[i] + 1]; ++k)
        ahead[w.corners[k]] = receiver.signedDistance(w.vertices[w.corners[k]]);
  // The edges and corners that may be on the silhouette: found once per light (not per
  // receiver) where the receiver's plane leaves the light whole, else for this receiver alone
  // among the whole light's candidates (clippedMeshSilhouette).
  thread_local MeshSilhouette own;
  thread_local std::vector<uint8_t> lightOnReceiver;
  lightOnReceiver.resize(n);
  for (size_t i = 0; i < n; ++i) lightOnReceiver[i] = onReceiver(s[i]);
  const MeshSilhouette& silhouette =
      wholeLight ? memoisedMeshSilhouette(faces, mesh, s, onPlane)
                 : (own = clippedMeshSilhouette(faces, mesh, whole, s, onPlane, ahead, lightOnReceiver, eps, near));
  for (size_t i = 0; i < n; ++i) {
    if (onReceiver(s[i])) continue;  // its rays never come back to the receiver
    for (const uint32_t e : silhouette.edges[i]) {
      if (!near.hasEdge(mesh, e)) continue;
      const auto [a, b] = w.edges[e];
      if (!(ahead[a] > onPlane) && !(ahead[b] > onPlane)) continue;
      Vec3 from = w.vertices[a], to = w.vertices[b];
      if (!(ahead[a] > 0)) from += (ahead[a] / (ahead[a] - ahead[b])) * (to - from);
      else if (!(ahead[b] > 0)) to += (ahead[b] / (ahead[b] - ahead[a])) * (from - to);
      if (wedgePlaneMisses(s[i], from - s[i], to - s[i], receiverFace.polygon, eps)) continue;
      add(vertexEdgeWedge({ElementRef::Kind::Vertex, uint32_t(i)}, {ElementRef::Kind::Edge, uint32_t(e)}, s[i], from,
                          to, eps));
    }
  }
  addContactLines(s, faces, mesh, receiverFace, onReceiver, tol, contactReach, add);
  for (size_t i = 0; i < n; ++i) {
    const Vec3 &p = s[i], &q = s[(i + 1) % n];
    if (onReceiver(p) && onReceiver(q)) continue;
    for (const auto& [v, from, to] : silhouette.corners[i]) {
      if (!near.hasCorner(mesh, v) || !(ahead[v] > onPlane)) continue;
      const Vec3 start = p + from * (q - p), end = p + to * (q - p), &corner = w.vertices[v];
      if (wedgePlaneMisses(corner, corner - start, corner - end, receiverFace.polygon, eps)) continue;
      add(edgeVertexWedge({ElementRef::Kind::Edge, uint32_t(i)}, {ElementRef::Kind::Vertex, uint32_t(v)}, start, end,
                          corner, eps));
    }
  }
}

SingleShadow finish(size_t light, uint32_t handle, const Face& receiver, SegmentCollector& segments,
                    Polygon2 penumbra, Polygon2 umbra) {
  SingleShadow out;
  out.light = uint32_t(light);
  out.occluder = wholeObject(handle);
  out.receiver = receiver.id;
  out.segments = segments.take();
  out.penumbra = std::move(penumbra);
  out.umbra = std::move(umbra);
  return out;
}

}  // namespace

std::optional<SingleShadow> castObjectShadow(const Scene& scene, size_t light, uint32_t handle,
                                             const Face& receiver, const PlaneFrame& frame, double contactReach) {
  const Tolerance tol = scene.tolerance();
  const double eps = tol.length();
  const Plane lightPlane = scene.lights().at(light).plane();
  // Light points behind the receiver's plane light none of it.
  const Polygon3 s = withoutFlatCorners(clipFront(scene.lights()[light].polygon, receiver.plane, eps), eps);
  if (s.size() < 3 || area(s) <= tol.area()) return std::nullopt;
  // A mesh's shadow is bounded by its box's (a superset) and has no umbra of its own.
  const MeshTopology* mesh = scene.convexSolid(handle) ? nullptr : scene.meshTopology(handle);
  const ConvexSolid* solidOf = mesh ? &mesh->box : scene.convexSolid(handle);
  if (!solidOf || solidOf->vertices.size() < 4) return std::nullopt;
  const ConvexSolid& solid = *solidOf;

  // R ∩ front of the light's plane (it emits forward only).
  Polygon2 outline;
  outline.reserve(receiver.polygon.size());
  for (const Vec3& p : receiver.polygon) outline.push_back(frame.to2D(p));
  const Polygon2 receiver2 = counterClockwise(outline);
  const Polygon2 base = clipFrontOf(receiver2, PlaneTrace::of(lightPlane, frame, tol), eps);
  if (base.size() < 3 || signedArea(base) <= tol.area()) return std::nullopt;

  const RegionClipper clipper(frame, tol);
  const std::vector<std::vector<Support>> supports = supportsOf(s, solid, eps);
  Polygon2 penumbra = penumbraRegion(base, s, solid, supports, clipper, eps);
  if (penumbra.empty()) return std::nullopt;
  // A light vertex on the receiver's plane: its cone meets the plane there only.
  auto onReceiver = [&](const Vec3& p) { return std::abs(receiver.plane.signedDistance(p)) <= eps; };
  Polygon2 umbra = !mesh && std::none_of(s.begin(), s.end(), onReceiver) ? umbraRegion(penumbra, supports, clipper)
                                                                          : Polygon2{};

  // Segments: the silhouette surfaces cut by the receiver's plane inside base.
  SegmentCollector segments(receiver2, penumbra, umbra, eps);
  auto add = [&](const std::optional<Wedge>& w, bool contact = false) {
    if (!w || wedgePlaneMisses(*w, receiver.polygon, eps)) return;
    const auto chord = wedgeChord(*w, base, frame, tol);
    if (chord && contact)
      segments.addWhole(chord->first, chord->second, SegmentKind::Contact, w->lightElement, w->occluderElement);
    else if (chord)
      segments.add(chord->first, chord->second, w->lightElement, w->occluderElement, [] { return true; });
  };
  const std::span<const Face> faces = scene.facesOfObject(handle);
  const size_t n = s.size();
  if (mesh) {
    meshSilhouetteWedges(s, scene.lights()[light].polygon, faces, *mesh, receiver, onReceiver, tol, contactReach, add);
    return finish(light, handle, receiver, segments, std::move(penumbra), std::move(umbra));
  }
  for (size_t i = 0; i < n; ++i) {
    if (onReceiver(s[i])) continue;  // its rays never come back to the receiver
    for (const Support& support : supports[i]) {
      const auto& [a, b] = solid.edges[support.edge];
      add(vertexEdgeWedge({ElementRef::Kind::Vertex, uint32_t(i)}, {ElementRef::Kind::Edge, uint32_t(support.edge)},
                          s[i], solid.vertices[a], solid.vertices[b], eps));
    }
  }
  for (size_t i = 0; i < n; ++i) {
    const Vec3 &p = s[i], &q = s[(i + 1) % n];
    if (onReceiver(p) && onReceiver(q)) continue;
    for (uint32_t v = 0; v < solid.vertices.size(); ++v)
      if (mayBeSilhouetteVertex(faces, solid.vertices[v], p, q, tol))
        add(edgeVertexWedge({ElementRef::Kind::Edge, uint32_t(i)}, {ElementRef::Kind::Vertex, uint32_t(v)}, p, q,
                            solid.vertices[v], eps));
  }
  return finish(light, handle, receiver, segments, std::move(penumbra), std::move(umbra));
}

}  // namespace penumbra
