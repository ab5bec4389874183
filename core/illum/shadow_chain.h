// A mesh's shadow seen from a point as a 1-chain (issue 35): the non-convex union of the
// central projections of its blocking faces without projecting and clipping them one by one.
//
// Seen from p, a face blocks when p lies strictly behind its plane (the single-sided rule).
// With every corner of the mesh strictly between p and the light's plane and ahead of p's
// own plane, the central projection onto the light's plane is one projective map with a
// positive denominator, so every blocking face projects with the same orientation. The
// number of blocking faces over a light point, w, is then the winding number of the sum
// of their projected boundaries. An edge run by two blocking faces in opposite directions
// (a regular edge between them) cancels: what is left are the edges where w changes, the
// silhouette seen from p and the open boundaries, each with the covered side on its left
// (a count > 1 where several faces run one edge alike). A light point is visible iff
// w = 0, so the union's boundary is where these edges have w = 0 on their right: exact
// (the same union as face by face) with O(faces) work to find the chain, not O(faces²) to
// clip the projections against each other. One thread.
#pragma once

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "core/geom/plane.h"
#include "core/geom/plane_frame.h"
#include "core/scene/mesh_topology.h"

namespace penumbra {

struct ChainEdge {
  Vec2 from{0.0}, to{0.0};
  int count = 1;  // faces running the edge this way, net
};

// Appends the chain of the mesh's faces `chainFaces`, of every face of the clusters
// `chainClusters` (MeshTopology::clusters) and of the faces summed in `summedEdges` (edges
// with net counts, as sumFaceEdges() gives them) — faces p lies strictly behind, whose
// corners all lie ahead of p's plane with a height over the light's plane in (0, pHeight),
// p's own — to `out`, in `frame` on the light's plane, oriented with the covered side on
// the left; an edge between a selected and an unselected face stays in the chain. Returns
// whether the selected faces project with positive area.
bool appendShadowChain(const MeshTopology& mesh, std::span<const uint32_t> chainFaces,
                       std::span<const uint32_t> chainClusters,
                       std::span<const std::pair<uint32_t, int>> summedEdges, const Vec3& p,
                       const Plane& lightPlane, double pHeight, const PlaneFrame& frame, double minArea,
                       std::vector<ChainEdge>& out);

// Several meshes' chains as one: edges with the same ends (coincident objects project
// bit for bit alike) are summed, run in opposite directions they cancel, so a boundary
// shared by two chains is counted once. Edges overlapping only in part stay separate.
void mergeChainEdges(std::vector<ChainEdge>& chain);

// The winding number of the chain around x (the number of blocking faces over x), leaving
// out edge `skip` (an index into chain; chain.size() leaves out none), counted along the
// ray from x in direction `ray` (nonzero). For x on an edge, a ray across it (not along
// it) never meets the ends of that edge or of its neighbours: the half-open crossing rule
// stays consistent with the edge left out.
int chainWinding(std::span<const ChainEdge> chain, const Vec2& x, const Vec2& ray, size_t skip);

}  // namespace penumbra
