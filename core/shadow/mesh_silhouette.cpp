#include "core/shadow/mesh_silhouette.h"

#include <algorithm>
#include <array>
#include <cstring>

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

MeshSilhouette meshSilhouette(std::span<const Face> faces, const MeshTopology& mesh, const Polygon3& s, double onPlane,
                              std::span<const double> ahead) {
  const auto inFront = [&](uint32_t v) { return ahead.empty() || ahead[v] > onPlane; };
  const ConvexSolid& w = mesh.welded;
  const size_t n = s.size();
  MeshSilhouette out;
  out.edges.resize(n);
  out.corners.resize(n);
  for (size_t i = 0; i < n; ++i) {
    for (uint32_t e = 0; e < w.edges.size(); ++e) {
      if (!inFront(w.edges[e].first) && !inFront(w.edges[e].second)) continue;
      const uint32_t* f = mesh.edgeFaces.data() + mesh.edgeStarts[e];
      if (mesh.regularEdge[e] && offSilhouette(faces[f[0]].plane, faces[f[1]].plane, s[i], onPlane)) continue;
      out.edges[i].push_back(e);
    }
    const Vec3 &p = s[i], &q = s[(i + 1) % n];
    for (uint32_t v = 0; v < w.vertices.size(); ++v) {
      if (!inFront(v)) continue;
      double from = 0, to = 1;
      if (mesh.regularVertex[v] && !silhouetteStretch(faces, mesh, v, p, q, onPlane, from, to)) continue;
      out.corners[i].push_back({v, from, to});
    }
  }
  return out;
}

const MeshSilhouette& memoisedMeshSilhouette(std::span<const Face> faces, const MeshTopology& mesh, const Polygon3& s,
                                             double onPlane) {
  struct Entry {
    uint64_t serial = 0;
    Polygon3 light;
    double onPlane = 0;
    uint64_t lastUse = 0;
    MeshSilhouette silhouette;
  };
  thread_local std::array<Entry, 4> memo;
  thread_local uint64_t uses = 0;
  Entry* oldest = &memo[0];
  for (Entry& entry : memo) {
    if (entry.serial == mesh.serial && entry.onPlane == onPlane && entry.light.size() == s.size() &&
        std::memcmp(entry.light.data(), s.data(), s.size() * sizeof(Vec3)) == 0) {
      entry.lastUse = ++uses;
      return entry.silhouette;
    }
    if (entry.lastUse < oldest->lastUse) oldest = &entry;
  }
  *oldest = Entry{mesh.serial, s, onPlane, ++uses, meshSilhouette(faces, mesh, s, onPlane)};
  return oldest->silhouette;
}

}  // namespace penumbra
