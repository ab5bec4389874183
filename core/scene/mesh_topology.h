// Any object's faces as one mesh (closed or open, convex or not): distinct corners, the
// edges between them and which faces use each edge and corner. Made when the object
// enters the scene or moves (Scene keeps one per object that is not closed convex), read
// by casting it whole from its silhouette (core/shadow/object_shadow.h) and by
// backprojecting it (core/illum/shadow_chain.h). Immutable.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "core/scene/convex_solid.h"
#include "core/scene/scene.h"

namespace penumbra {

struct MeshTopology {
  static constexpr uint32_t kNoEdge = 0xffffffffu;
  // Welded corners, face corners and distinct edges (first < second), as ConvexSolid.
  ConvexSolid welded;
  // Per face corner k (an index into welded.corners): the edge from corner k to the next
  // corner of its face (kNoEdge where the two corners weld into one), and whether the face runs it from edge.first to edge.second.
  std::vector<uint32_t> cornerEdge;
  std::vector<uint8_t> cornerForward;
  // The faces using each edge: edgeFaces[edgeStarts[e] .. edgeStarts[e + 1]).
  std::vector<uint32_t> edgeStarts, edgeFaces;
  // The faces using each corner: vertexFaces[vertexStarts[v] .. vertexStarts[v + 1]).
  std::vector<uint32_t> vertexStarts, vertexFaces;
  // Per edge: two faces that run it in opposite directions (a manifold, consistently
  // oriented edge). Per corner: every edge through it is so.
  std::vector<uint8_t> regularEdge, regularVertex;
  // Per face: some corner lies more than onPlane in front of its plane (the mesh can
  // shadow itself there; object_shadow.h casts it on that face as one occluder). All set
  // past faces × corners = 5·10⁷.
  std::vector<uint8_t> facesSomethingAhead;
  // The faces grouped by place, each group in a ball around its corners: a point's cone
  // over the light that misses a ball misses all its faces (Backprojection::occludeMesh
  // looks at the faces of the balls it meets only). Group g: clusterFaces[first, last).
  struct Cluster {
    Vec3 centre{0.0};
    double radius = 0;
    uint32_t first = 0, last = 0;
  };
  static constexpr size_t kClusterFaces = 32;
  std::vector<Cluster> clusters;
  // The clusters' balls as the tree of the median splits that made them, in preorder: node i's
  // ball holds the balls of clusters [firstCluster, endCluster) (ball.first, ball.last: their
  // faces, as a cluster's), its first child is node i + 1 and `skip` the node after its
  // subtree. A leaf is one cluster with that cluster's own ball. A pass over the clusters a
  // point's cone meets skips a subtree whose ball misses it (forEachClusterMeeting), instead
  // of testing every cluster: on a model's own 20 k faces each point tested 1,024 balls to
  // keep ~20.
  struct ClusterNode {
    Cluster ball;
    uint32_t firstCluster = 0, endCluster = 0, skip = 0;
  };
  std::vector<ClusterNode> clusterTree;
  // The cluster holding each face.
  std::vector<uint32_t> faceCluster;
  std::vector<uint32_t> clusterFaces;
  // clusterPlanes[i]: the plane of face clusterFaces[i], copied in cluster order so a
  // point's pass over the faces its cone meets reads them in a row (the faces themselves
  // are ~200 bytes apart).
  std::vector<Plane> clusterPlanes;
  // Per cluster: its faces' edges summed as a point's chain sums them when every face of the
  // cluster blocks it (core/illum/shadow_chain.h; run both ways inside the cluster they
  // cancel): cluster c's (edge, net count) are clusterChain[clusterChainStarts[c] .. [c + 1]),
  // only those with a nonzero count, in the order its faces first run them.
  std::vector<uint32_t> clusterChainStarts;
  std::vector<std::pair<uint32_t, int>> clusterChain;
  // The axis-aligned box around the corners as a closed convex solid (a conservative
  // stand-in for the mesh where only a superset of its shadow is needed).
  ConvexSolid box;
  // Distinct for every topology made (a memo's key: core/illum/mesh_box_chain.h), kept by copies.
  uint64_t serial = 0;

  // From the object's world faces (Scene::facesOfObject order) and the scene's onPlane().
  static MeshTopology of(std::span<const Face> faces, double onPlane);

  // visit(c) for each cluster c whose ball `misses` does not reject, in ascending order, while
  // visit returns true. `misses(const Cluster&)` must reject every ball inside a ball it rejects
  // (the ball lies beyond a plane, or farther than a distance from a box, by its radius): then
  // the clusters visited are exactly those a pass over every cluster keeps. A node's ball is
  // padded well past the rounding of such a test (clusterTree).
  template <class Misses, class Visit>
  void forEachClusterMeeting(const Misses& misses, const Visit& visit) const {
    for (size_t i = 0; i < clusterTree.size();) {
      const ClusterNode& node = clusterTree[i];
      if (misses(node.ball)) {
        i = node.skip;
        continue;
      }
      if (node.endCluster - node.firstCluster == 1 && !visit(node.firstCluster)) return;
      ++i;
    }
  }
};

// Adds face f's edges to their net direction counts (+1 run from edge.first to .second, −1
// back), listing in `touched` each edge whose count leaves 0.
inline void addFaceEdges(const MeshTopology& mesh, uint32_t f, std::vector<int>& net, std::vector<uint32_t>& touched) {
  for (uint32_t k = mesh.welded.faceStarts[f]; k < mesh.welded.faceStarts[f + 1]; ++k) {
    const uint32_t e = mesh.cornerEdge[k];
    if (e == MeshTopology::kNoEdge) continue;
    if (net[e] == 0) touched.push_back(e);
    net[e] += mesh.cornerForward[k] ? 1 : -1;
  }
}

// The edges of `faces` with their net direction counts (run both ways they cancel), appended
// to `out` as (edge, count ≠ 0) in the order the faces first run them. `net` holds one zero
// per edge of the mesh and is left so; `touched` is scratch.
void sumFaceEdges(const MeshTopology& mesh, std::span<const uint32_t> faces, std::vector<int>& net,
                  std::vector<uint32_t>& touched, std::vector<std::pair<uint32_t, int>>& out);

}  // namespace penumbra
