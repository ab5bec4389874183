// A mesh's potential silhouette seen from a light polygon (object_shadow.h states the rule
// and its proof): per light vertex, the edges that can be on the silhouette from it (every
// edge but a regular one whose two faces it lies off on one side); per light edge, the
// corners that can be on the silhouette from some point of it, with the stretch of the edge
// they can be from. None of it depends on the receiver, so a mesh casting on each of its
// own thousands of faces finds it once per light, not once per face (it was O(faces) per
// receiver: the 6,006-triangle bowl's cast was 43 % such loops). Memoised per thread.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/geom/polygon.h"
#include "core/scene/mesh_topology.h"

namespace penumbra {

// A set of a mesh's clusters (MeshTopology::clusters): c is in it when stamps[c] == stamp; with
// no stamps, every cluster. An edge counts as in it when its first face's cluster is, a corner
// when its first face's is (each lies in that cluster's ball).
struct ClusterSet {
  std::span<const uint32_t> stamps;
  uint32_t stamp = 0;
  std::span<const uint32_t> list;  // with stamps: the clusters in it, ascending
  bool has(uint32_t cluster) const { return stamps.empty() || stamps[cluster] == stamp; }
  bool hasEdge(const MeshTopology& mesh, uint32_t e) const {
    return stamps.empty() || has(mesh.faceCluster[mesh.edgeFaces[mesh.edgeStarts[e]]]);
  }
  bool hasCorner(const MeshTopology& mesh, uint32_t v) const {
    return stamps.empty() || mesh.vertexStarts[v] == mesh.vertexStarts[v + 1] ||
           has(mesh.faceCluster[mesh.vertexFaces[mesh.vertexStarts[v]]]);
  }
};

struct MeshSilhouette {
  struct Corner {
    uint32_t vertex = 0;     // a welded corner of the mesh
    double from = 0, to = 1; // the stretch of the light edge it may be on the silhouette from
  };
  std::vector<std::vector<uint32_t>> edges;   // per light vertex i, ascending
  std::vector<std::vector<Corner>> corners;   // per light edge (i, i + 1), ascending by vertex
};

// Whether light point s is off both faces' planes on one side (both strictly front or
// both strictly back) of a regular edge: then the edge is on no silhouette seen from s.
bool offSilhouette(const Plane& a, const Plane& b, const Vec3& s, double onPlane);

// The stretch [from, to] of the light edge pq from whose points regular corner v may be on
// the mesh's silhouette (see the .cpp); false when there is none.
bool silhouetteStretch(std::span<const Face> faces, const MeshTopology& mesh, uint32_t v, const Vec3& p, const Vec3& q,
                       double onPlane, double& from, double& to);

// The potential silhouette of the mesh (its world faces `faces`) from light polygon s. With
// `ahead` (each welded corner's distance in front of a receiver's plane), only what that
// receiver can be shadowed by: edges with an end, and corners, more than onPlane in front.
MeshSilhouette meshSilhouette(std::span<const Face> faces, const MeshTopology& mesh, const Polygon3& s, double onPlane,
                              std::span<const double> ahead = {});

// The same (without `ahead`), kept per thread for the last few (mesh, s, onPlane) asked;
// valid until the next call on this thread. For a light not clipped by the receiver's plane,
// the same s for every receiver; a clipped one (a model's face whose plane cuts the light)
// is its receiver's own and is better computed with `ahead`.
const MeshSilhouette& memoisedMeshSilhouette(std::span<const Face> faces, const MeshTopology& mesh, const Polygon3& s,
                                             double onPlane);

// A receiver whose plane clips the light (a model's face; s = the clipped part of `whole`)
// asks the same as meshSilhouette(faces, mesh, s, onPlane, ahead), but only for what it uses:
// nothing from a light vertex with onReceiver[i] set, nor from a light edge with both ends so
// (their rays never come back to it; those entries stay empty). Each vertex and edge of s lies
// on an edge of `whole` (within `slack`, a length tolerance): along a light edge pq, an edge of
// the mesh whose two faces have p and q both more than onPlane + 2·slack on one side (the same
// side for all four) is off the silhouette from every point near pq, and so is a corner whose
// faces all have p and q so (the distances are affine along pq and move by at most slack off
// it). So only the rest, found once per whole light (memoised per thread), is tested at s's
// own points, by the same tests on the same numbers: O(candidates), not O(mesh), per receiver.
// An item of s on no single edge of `whole` is tested against the whole mesh. Only items in
// `near` are kept (the receiver's shaft: the rest cannot shadow it, object_shadow.cpp), and
// only they are tested.
MeshSilhouette clippedMeshSilhouette(std::span<const Face> faces, const MeshTopology& mesh, const Polygon3& whole,
                                     const Polygon3& s, double onPlane, std::span<const double> ahead,
                                     std::span<const uint8_t> onReceiver, double slack, ClusterSet near = {});

}  // namespace penumbra
