// What a mesh's faces do for every point of a small box (issue 35). A point's chain
// (shadow_chain.h) is the summed boundary of the faces it lies strictly behind, and over a
// box a few centimetres wide most faces of a model are behind every point of it or behind
// none: only those whose plane crosses the box differ between its points. So the faces
// behind all of it are summed once per box (inner edges cancel), and a point of the box adds
// only the crossing faces it is behind: the same set of faces as the point's own pass over
// all of them, with work in the crossing faces and the summed edges, not in every face.
//
// The chain then holds every blocking face, also those whose projection misses the light
// (a point's own pass leaves out the clusters outside its cone over the light): each such
// face's boundary is closed and covers no light point, so the winding over the light, and
// the visible part, are the same. A face with a corner that is not usable from every point
// of the box (ahead of the receiver's plane, beyond the light's and short of the box's least
// height over it by the 1e-3 margin of Backprojection::occludeMesh) is `special`: each point
// decides it as its own pass does. Where a special face blocks the point on its own (one
// touching the floor the model rests on, seen from beside its contact), the point takes its
// own pass. A box with many special faces (a receiver on the mesh itself, or cutting through
// it) is not used.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "core/geom/plane.h"
#include "core/geom/tolerance.h"
#include "core/scene/mesh_topology.h"

namespace penumbra {

struct MeshBoxChain {
  // The box saves work (few special faces, as above); when false the rest is empty and a
  // point takes its own pass.
  bool usable = false;
  // The faces every point of the box lies more than onPlane behind, summed (sumFaceEdges).
  std::vector<std::pair<uint32_t, int>> behindAll;
  // Indices into MeshTopology::clusterFaces / clusterPlanes of the faces whose plane's
  // onPlane offset crosses the box: each point decides them itself.
  std::vector<uint32_t> crossing;
  // Indices as `crossing` of the faces with a corner not usable from every point of the box.
  std::vector<uint32_t> special;
};

// A box is used while at most 1/kMostSpecialShare of the mesh's faces are special.
inline constexpr size_t kMostSpecialShare = 8;

// The box holding p, for `mesh` seen from the receiver plane with unit normal n through p
// and lit from lightPlane: one of a grid of cubes 1/kMeshBoxDivisions of the mesh's box
// diagonal wide, cut to a slab a few length tolerances thick around the receiver's plane
// (n·x within it; flat where n is an axis) (so the same p always finds the same box, whatever
// was asked before), or
// null where the grid does not reach (a degenerate mesh, p too far from the origin for the
// grid's integers). Memoised per thread (the last few boxes asked); the reference is valid
// until the next call on the same thread.
inline constexpr double kMeshBoxDivisions = 16;
const MeshBoxChain* meshBoxChain(const MeshTopology& mesh, const Vec3& p, const Vec3& n, std::span<const Vec3> light,
                                 const Plane& lightPlane, const Tolerance& tolerance);

// The same, computed for the box [low, high] (no memo): tests and the function above. The
// points asked have n·p at most highestReceiver (the receiver's plane through each of them).
MeshBoxChain makeMeshBoxChain(const MeshTopology& mesh, const Vec3& low, const Vec3& high, const Vec3& n,
                              std::span<const Vec3> light, const Plane& lightPlane, const Tolerance& tolerance,
                              double highestReceiver = INFINITY);

}  // namespace penumbra
