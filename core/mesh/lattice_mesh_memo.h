// The display mesh of one receiver meshed from its lattice squares instead of its DM-tree cells
// (docs/DESIGN.md "Lattice display"): each square of the face's display lattice is fanned and
// refined by the same tests as a cell's piece (cell_refinement.h), every point lit exactly from
// the occluder list of the DM-tree cell holding it. No DM vertex or edge is in this mesh, so the
// DM's vertex values are not read: under a tessellated model the floor's DM holds thousands of
// vertices a square (silhouette lines crossing in the penumbra), where a square needs tens of
// points. Used where displaysFromLattice (lattice_display_rule.h) says so; one writer per memo.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "core/geom/plane_frame.h"
#include "core/geom/polygon.h"
#include "core/mesh/cell_lighting.h"
#include "core/mesh/mesh.h"
#include "core/mesh/receiver_mesh_memo.h"
#include "core/util/parallel.h"

namespace penumbra {

class LatticeMeshMemo {
 public:
  // Squares are refined at this share of the grid's tolerance: their test points lie farther
  // from the penumbra's slope breaks (D1 lines) than a cell's, which has them on its outline.
  // At the full tolerance the worst of 20,000 random floor points under the teapot 992 was
  // 1.38 % of the local level; at half, 0.34 % (the cells' mesh: 0.54 %; BENCHMARKS.md).
  static constexpr double kToleranceShare = 0.5;

  // Brings the squares and chunks up to date with the source's tree and the scene's radiances
  // (a new radiance assembles every chunk again, lighting no square), adding what it did to
  // `counters` (squares count as cells). Squares holding a part of a cell touched since the
  // last call are lit again; one whose points, values and triangles come out the same keeps its
  // chunks. Chunks are assembled from their squares in square order, so the result is bit for
  // bit what a fresh memo gives. `progress` (may be empty) counts the squares (units(): the
  // untouched at once, the rest as they are lit) and beats per chunk assembled.
  void update(const Scene& scene, const MeshSource& source, MeshGrid grid, MeshMemoCounters& counters,
              const Parallel& parallel, const MeshProgress& progress = {});
  // The squares the next update() with these arguments counts: it splits the face by the lattice
  // now where the memo does not fit them yet (update() then keeps that).
  size_t units(const Scene& scene, const MeshSource& source, MeshGrid grid);
  const std::map<MeshChunkKey, std::shared_ptr<const ReceiverMesh>>& chunks() const { return chunks_; }
  // Squares whose refinement stopped at its point cap short of the tolerance.
  size_t cappedSquares() const;

  // One square's output: its points (loop, centre if any, added points) with each light's
  // value, and its triangles (local indices, counter-clockwise).
  struct Square {
    std::vector<Vec2> points;
    std::vector<VertexLight> lights;  // points × lights
    std::vector<std::array<uint32_t, 3>> triangles;
    bool capped = false;
    bool sameAs(const Square& other) const;
  };

 private:
  void reset(const Scene& scene, const MeshSource& source, const MeshGrid& grid);
  // The squares overlapping a cell touched since the last call, ascending.
  std::vector<uint32_t> touchedSquares(const MeshSource& source) const;
  void assembleChunk(const Scene& scene, const MeshSource& source, const MeshChunkKey& key, ReceiverMesh& mesh) const;

  PlaneFrame frame_;
  MeshGrid grid_;
  double eps_ = 0;
  bool fresh_ = true;    // no square lit yet
  uint64_t stamp_ = 0;   // HalfEdgeMesh::stampNow() at the last call
  std::vector<Vec3> radiance_;
  std::vector<Polygon2> outlines_;               // the face's lattice squares (convex, CCW)
  std::vector<MeshChunkKey> chunkOf_;            // per square
  std::map<std::pair<int64_t, int64_t>, std::vector<uint32_t>> squaresAt_;  // lattice index → squares
  std::vector<Square> squares_;                  // per square
  std::map<MeshChunkKey, std::vector<uint32_t>> chunkSquares_;  // ascending
  std::map<MeshChunkKey, std::shared_ptr<const ReceiverMesh>> chunks_;
};

}  // namespace penumbra
