// The display mesh of one receiver, kept per cell and per chunk between calls: what each DM-tree
// cell emitted and the inputs it came from, so only cells touched since the last call are lit
// again. Held per receiver by a DisplayMeshMemo (display_mesh_memo.h); one writer per memo,
// different memos may update in parallel.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "core/geom/plane_frame.h"
#include "core/mesh/cell_lighting.h"
#include "core/mesh/mesh.h"
#include "core/util/parallel.h"

namespace penumbra {

// What mesh calls did: live cells kept / lit afresh, chunks assembled again / kept.
struct MeshMemoCounters {
  size_t cellsReused = 0, cellsLit = 0;
  size_t chunksMeshed = 0, chunksKept = 0;
  // Refinement's test points (cell_refinement.h): values asked, and the points kept (a test
  // failed there). Most of a refined mesh's time is the asked values.
  size_t testPoints = 0, testPointsKept = 0;
  MeshMemoCounters& operator+=(const MeshMemoCounters& o) {
    cellsReused += o.cellsReused, cellsLit += o.cellsLit;
    chunksMeshed += o.chunksMeshed, chunksKept += o.chunksKept;
    testPoints += o.testPoints, testPointsKept += o.testPointsKept;
    return *this;
  }
};

// How a memo's update reports as it goes, from any of its threads: `units` more cells (a lattice
// memo's squares) done, or 0 for "still at work" (a chunk being assembled). It may throw to end
// the update: the memo is then only fit to be dropped. Empty: no reports.
using MeshProgress = std::function<void(size_t units)>;

// The display grid: lattice spacing (0: none), chunk side in lattice squares (0: one chunk),
// how far each piece's triangles are refined (core/mesh/cell_refinement.h), and the DM vertices
// in one lattice square above which a receiver may be meshed from its squares instead of its
// cells (lattice_display_rule.h; 0: never), with the tolerance those squares are refined to.
struct MeshGrid {
  double spacing = 0;
  int chunkSquares = 0;
  RefineSettings refine;
  uint32_t latticeAbove = 0;
  // refine.tolerance, or where the cells are not refined (0) the engine's recommended one: an
  // unrefined square would be far coarser than the DM cells it replaces (0: no lattice display).
  double latticeTolerance = 0;
  // A memo is only valid for the grid it was made with (the engine keeps one grid).
  bool operator==(const MeshGrid&) const = default;
};

class ReceiverMeshMemo {
 public:
  // Brings the cells and chunks up to date with the source's tree and the scene's radiances
  // (a new radiance assembles every chunk again, relighting no cell), adding what it did to
  // `counters`. Cells are triangulated (cut by the lattice); vertices repeat once per side where
  // the value jumps (contact edges, cells in a light's umbra). A changed chunk is assembled again
  // from its cells' pieces in cell order, so it is bit for bit what a fresh memo gives.
  // Cells are lit on `parallel`'s threads, each into its own slot: the same bytes on any count.
  // `progress` (may be empty) counts the tree's cell slots (units(): the dead and the untouched
  // at once, the rest as they are lit, kCellsPerReport at a time) and beats per chunk assembled,
  // so a caller sees a large receiver's meshing move (the floor of a dense room is most of it).
  void update(const Scene& scene, const MeshSource& source, MeshGrid grid, MeshMemoCounters& counters,
              const Parallel& parallel, const MeshProgress& progress = {});
  static size_t units(const MeshSource& source) { return source.tree.mesh().cellSlots(); }
  static constexpr size_t kCellsPerReport = 16;
  // The non-empty chunks' meshes, in key order; an unchanged chunk keeps its object.
  const std::map<MeshChunkKey, std::shared_ptr<const ReceiverMesh>>& chunks() const { return chunks_; }
  // Live cells whose refinement stopped at its point cap short of the tolerance.
  size_t cappedCells() const;

 private:
  friend class MeshMemoUpdate;
  PlaneFrame frame_;
  MeshGrid grid_;
  double eps_ = 0;
  uint64_t stamp_ = 0;  // HalfEdgeMesh::stampNow() at the last call: cells touched later changed
  std::vector<Vec3> radiance_;   // the lights' radiances the chunks were summed with
  std::vector<CellMemo> cells_;  // by CellId index
  std::map<MeshChunkKey, std::shared_ptr<const ReceiverMesh>> chunks_;
  std::map<MeshChunkKey, std::vector<uint32_t>> chunkCells_;  // cells with a piece in each chunk, ascending
};

}  // namespace penumbra
