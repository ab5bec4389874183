#include "core/shadow/mesh_silhouette.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <initializer_list>

namespace penumbra {

// Whether light point s is off both faces' planes on one side (both strictly front or
// both strictly back) of a regular edge: then the edge is on no silhouette seen from s.
bool offSilhouette(const Plane& a, const Plane& b, const Vec3& s, double onPlane) {
  const double da = a.signedDistance(s), db = b.signedDistance(s);
  return (da > onPlane && db > onPlane) || (da < -onPlane && db < -onPlane);
}

// The stretch: not where every face through v has the point more than onPlane()
// in front (or every one behind). Each face's side changes once along pq, so "all in
// front" and "all behind" are two disjoint intervals; the stretch is the hull of what they
// leave. False when they cover pq.
bool silhouetteStretch(std::span<const Face> faces, const MeshTopology& mesh, uint32_t v, const Vec3& p, const Vec3& q,
                       double onPlane, double& from, double& to) {
  double frontLow = 0, frontHigh = 1, backLow = 0, backHigh = 1;  // the two intervals
  for (uint32_t k = mesh.vertexStarts[v]; k < mesh.vertexStarts[v + 1]; ++k) {
    const Plane& plane = faces[mesh.vertexFaces[k]].plane;
    const double dp = plane.signedDistance(p), dq = plane.signedDistance(q);
    // Where (1 − t) dp + t dq > onPlane, and where it is < −onPlane.
    auto keep = [&](double a, double b, double& low, double& high) {  // {t : a + t (b − a) > 0}
      if (a > 0 && b > 0) return;
      if (!(a > 0) && !(b > 0)) {
        low = 1, high = 0;
        return;
      }
      const double t = a / (a - b);
      if (a > 0) high = std::min(high, t);
      else low = std::max(low, t);
    };
    keep(dp - onPlane, dq - onPlane, frontLow, frontHigh);
    keep(-dp - onPlane, -dq - onPlane, backLow, backHigh);
  }
  from = 0, to = 1;
  // An interval holding an end moves that end past it (the two never touch: a gap of
  // 2·onPlane lies between them along every face's distance).
  for (int pass = 0; pass < 2; ++pass) {
    if (frontLow <= from && from <= frontHigh) from = frontHigh;
    if (backLow <= from && from <= backHigh) from = backHigh;
    if (frontLow <= to && to <= frontHigh) to = frontLow;
    if (backLow <= to && to <= backHigh) to = backLow;
  }
  return from < to;
}

namespace {

// What make() gives for (mesh, light polygon, onPlane, slack), kept per thread and per caller
// for the last four asked (the light compared bit for bit); valid until the next call.
template <class Value, class Make>
const Value& memoisedPerLight(const MeshTopology& mesh, const Polygon3& light, double onPlane, double slack,
                              Make&& make) {
  struct Entry {
    uint64_t serial = 0;
    Polygon3 light;
    double onPlane = 0, slack = 0;
    uint64_t lastUse = 0;
    Value value;
  };
  thread_local std::array<Entry, 4> memo;
  thread_local uint64_t uses = 0;
  Entry* oldest = &memo[0];
  for (Entry& entry : memo) {
    if (entry.serial == mesh.serial && entry.onPlane == onPlane && entry.slack == slack &&
        entry.light.size() == light.size() &&
        std::memcmp(entry.light.data(), light.data(), light.size() * sizeof(Vec3)) == 0) {
      entry.lastUse = ++uses;
      return entry.value;
    }
    if (entry.lastUse < oldest->lastUse) oldest = &entry;
  }
  *oldest = Entry{mesh.serial, light, onPlane, slack, ++uses, make()};
  return oldest->value;
}

// Whether mesh edge e may be on the silhouette from light point x (every edge that is not
// regular may), and corner v from some point of light edge pq, with its stretch.
bool edgeMayBeOn(std::span<const Face> faces, const MeshTopology& mesh, uint32_t e, const Vec3& x, double onPlane) {
  const uint32_t* f = mesh.edgeFaces.data() + mesh.edgeStarts[e];
  return !(mesh.regularEdge[e] && offSilhouette(faces[f[0]].plane, faces[f[1]].plane, x, onPlane));
}

void keepEdges(std::span<const Face> faces, const MeshTopology& mesh, const Vec3& x, double onPlane,
               std::span<const double> ahead, const std::vector<uint32_t>* among, std::vector<uint32_t>& out,
               ClusterSet near = {}) {
  const ConvexSolid& w = mesh.welded;
  const auto inFront = [&](uint32_t v) { return ahead.empty() || ahead[v] > onPlane; };
  auto keep = [&](uint32_t e) {
    if (!near.hasEdge(mesh, e)) return;
    if (!inFront(w.edges[e].first) && !inFront(w.edges[e].second)) return;
    if (edgeMayBeOn(faces, mesh, e, x, onPlane)) out.push_back(e);
  };
  if (among) {  // else every edge
    for (const uint32_t e : *among) keep(e);
  } else {
    for (uint32_t e = 0; e < w.edges.size(); ++e) keep(e);
  }
}

void keepCorners(std::span<const Face> faces, const MeshTopology& mesh, const Vec3& p, const Vec3& q, double onPlane,
                 std::span<const double> ahead, const std::vector<uint32_t>* among,
                 std::vector<MeshSilhouette::Corner>& out, ClusterSet near = {}) {
  auto keep = [&](uint32_t v) {
    if (!near.hasCorner(mesh, v)) return;
    if (!ahead.empty() && !(ahead[v] > onPlane)) return;
    double from = 0, to = 1;
    if (mesh.regularVertex[v] && !silhouetteStretch(faces, mesh, v, p, q, onPlane, from, to)) return;
    out.push_back({v, from, to});
  };
  if (among) {  // else every corner
    for (const uint32_t v : *among) keep(v);
  } else {
    for (uint32_t v = 0; v < mesh.welded.vertices.size(); ++v) keep(v);
  }
}

}  // namespace

MeshSilhouette meshSilhouette(std::span<const Face> faces, const MeshTopology& mesh, const Polygon3& s, double onPlane,
                              std::span<const double> ahead) {
  const size_t n = s.size();
  MeshSilhouette out;
  out.edges.resize(n);
  out.corners.resize(n);
  for (size_t i = 0; i < n; ++i) {
    keepEdges(faces, mesh, s[i], onPlane, ahead, nullptr, out.edges[i]);
    keepCorners(faces, mesh, s[i], s[(i + 1) % n], onPlane, ahead, nullptr, out.corners[i]);
  }
  return out;
}

namespace {

// Per edge pq of a whole light: the mesh's edges and corners not surely off the silhouette
// from every point within slack of pq (mesh_silhouette.h, clippedMeshSilhouette), ascending.
struct Candidates {
  std::vector<std::vector<uint32_t>> edges, corners;
};

Candidates candidatesAlong(std::span<const Face> faces, const MeshTopology& mesh, const Polygon3& whole, double onPlane,
                           double slack) {
  const double margin = onPlane + 2 * slack;
  const ConvexSolid& w = mesh.welded;
  const size_t n = whole.size();
  Candidates out;
  out.edges.resize(n);
  out.corners.resize(n);
  for (size_t j = 0; j < n; ++j) {
    const Vec3 &p = whole[j], &q = whole[(j + 1) % n];
    // Every plane in `planes` with p and q both beyond margin on one side, the same for all.
    auto oneSide = [&](auto&& planes) {
      bool front = true, back = true;
      planes([&](const Plane& plane) {
        const double dp = plane.signedDistance(p), dq = plane.signedDistance(q);
        front = front && dp > margin && dq > margin;
        back = back && dp < -margin && dq < -margin;
      });
      return front || back;
    };
    for (uint32_t e = 0; e < w.edges.size(); ++e) {
      const uint32_t* f = mesh.edgeFaces.data() + mesh.edgeStarts[e];
      if (mesh.regularEdge[e] && oneSide([&](auto&& at) { at(faces[f[0]].plane), at(faces[f[1]].plane); })) continue;
      out.edges[j].push_back(e);
    }
    for (uint32_t v = 0; v < w.vertices.size(); ++v) {
      if (mesh.regularVertex[v] && oneSide([&](auto&& at) {
            for (uint32_t k = mesh.vertexStarts[v]; k < mesh.vertexStarts[v + 1]; ++k) at(faces[mesh.vertexFaces[k]].plane);
          }))
        continue;
      out.corners[j].push_back(v);
    }
  }
  return out;
}

const Candidates& memoisedCandidates(std::span<const Face> faces, const MeshTopology& mesh, const Polygon3& whole,
                                     double onPlane, double slack) {
  return memoisedPerLight<Candidates>(mesh, whole, onPlane, slack,
                                      [&] { return candidatesAlong(faces, mesh, whole, onPlane, slack); });
}

// Whether x lies within slack of segment pq.
bool nearSegment(const Vec3& p, const Vec3& q, const Vec3& x, double slack) {
  const Vec3 d = q - p;
  const double length2 = glm::dot(d, d);
  const double t = length2 > 0 ? std::clamp(glm::dot(x - p, d) / length2, 0.0, 1.0) : 0.0;
  return glm::length(p + t * d - x) <= slack;
}

// The edge of `whole` that every point of `points` lies near, or whole.size() when none does.
size_t edgeHolding(const Polygon3& whole, std::initializer_list<Vec3> points, double slack) {
  const size_t n = whole.size();
  for (size_t j = 0; j < n; ++j)
    if (std::all_of(points.begin(), points.end(),
                    [&](const Vec3& x) { return nearSegment(whole[j], whole[(j + 1) % n], x, slack); }))
      return j;
  return n;
}

}  // namespace

MeshSilhouette clippedMeshSilhouette(std::span<const Face> faces, const MeshTopology& mesh, const Polygon3& whole,
                                     const Polygon3& s, double onPlane, std::span<const double> ahead,
                                     std::span<const uint8_t> onReceiver, double slack, ClusterSet near) {
  const Candidates& candidates = memoisedCandidates(faces, mesh, whole, onPlane, slack);
  const size_t n = s.size();
  MeshSilhouette out;
  out.edges.resize(n);
  out.corners.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec3 &p = s[i], &q = s[(i + 1) % n];
    if (!onReceiver[i]) {
      const size_t j = edgeHolding(whole, {p}, slack);
      keepEdges(faces, mesh, p, onPlane, ahead, j < whole.size() ? &candidates.edges[j] : nullptr, out.edges[i], near);
    }
    if (!onReceiver[i] || !onReceiver[(i + 1) % n]) {
      const size_t j = edgeHolding(whole, {p, q}, slack);
      keepCorners(faces, mesh, p, q, onPlane, ahead, j < whole.size() ? &candidates.corners[j] : nullptr,
                  out.corners[i], near);
    }
  }
  return out;
}

const MeshSilhouette& memoisedMeshSilhouette(std::span<const Face> faces, const MeshTopology& mesh, const Polygon3& s,
                                             double onPlane) {
  return memoisedPerLight<MeshSilhouette>(mesh, s, onPlane, 0.0, [&] { return meshSilhouette(faces, mesh, s, onPlane); });
}

}  // namespace penumbra
