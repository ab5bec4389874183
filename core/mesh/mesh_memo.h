// The display mesh of one receiver, kept per cell and per chunk between calls: what each DM-tree
// cell emitted and the inputs it came from, so only cells touched since the last call are lit
// again. Owned by one engine; one writer per memo, different memos may update in parallel.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "core/dmtree/dm_tree.h"
#include "core/geom/plane_frame.h"
#include "core/illum/vertex_illumination.h"
#include "core/mesh/mesh.h"

namespace penumbra {

// A display chunk: the lattice-aligned block (x, y) of a receiver's 2D frame.
struct MeshChunkKey {
  int64_t x = 0, y = 0;
  auto operator<=>(const MeshChunkKey&) const = default;
};

// What mesh calls did: live cells kept / lit afresh, chunks assembled again / kept.
struct MeshMemoCounters {
  size_t cellsReused = 0, cellsLit = 0;
  size_t chunksMeshed = 0, chunksKept = 0;
  MeshMemoCounters& operator+=(const MeshMemoCounters& o) {
    cellsReused += o.cellsReused, cellsLit += o.cellsLit;
    chunksMeshed += o.chunksMeshed, chunksKept += o.chunksKept;
    return *this;
  }
};

// What meshing a receiver reads: its tree and its vertices' values (the engine's Receiver).
struct MeshSource {
  FaceId face;
  const PlaneFrame& frame;
  const DmTree& tree;
  const std::vector<VertexIrradiance>& values;           // by VertexId
  const std::vector<std::vector<VertexLight>>& perLight;  // [vertex][light]
};

// The display grid: lattice spacing (0: none) and chunk side in lattice squares (0: one chunk).
struct MeshGrid {
  double spacing = 0;
  int chunkSquares = 0;
};

class ReceiverMeshMemo {
 public:
  // Brings the cells and chunks up to date with the source's tree, adding what it did to
  // `counters`. Cells are triangulated (cut by the lattice); vertices repeat once per side where
  // the value jumps (contact edges, cells in a light's umbra). A changed chunk is assembled again
  // from its cells' pieces in cell order, so it is bit for bit what a fresh memo gives.
  void update(const Scene& scene, const MeshSource& source, MeshGrid grid, MeshMemoCounters& counters);
  // The non-empty chunks' meshes, in key order; an unchanged chunk keeps its object.
  const std::map<MeshChunkKey, std::shared_ptr<const ReceiverMesh>>& chunks() const { return chunks_; }

  // What one cell emitted, and a fingerprint of what that depends on (its outline,
  // occluder list, the listed faces' polygons, its corners' values): an equal
  // fingerprint means the cell would emit the same again (a 64-bit collision, ~2⁻⁶⁴ a
  // compare, would keep a stale cell). Keeping the inputs themselves cost ~1.5 kB a
  // cell, most of a dense room's memory. Buffers are reused from cell to cell.
  struct CellMemo {
    bool valid = false;
    uint64_t inputs = 0;
    // The output: builder calls (point, value) in order, and triangles into them,
    // per piece (a lattice square's part of the cell): its chunk and where its
    // points and triangles start (one more entry closes the last piece).
    std::vector<std::pair<Vec2, VertexIrradiance>> emitted;
    std::vector<std::array<uint32_t, 3>> triangles;
    std::vector<MeshChunkKey> pieceChunks;
    std::vector<uint32_t> pieceEmitted, pieceTriangles;
    void clearOutput();
  };

 private:
  friend class MeshMemoUpdate;
  PlaneFrame frame_;
  MeshGrid grid_;
  double eps_ = 0;
  uint64_t stamp_ = 0;  // HalfEdgeMesh::stampNow() at the last call: cells touched later changed
  std::vector<CellMemo> cells_;  // by CellId index
  std::map<MeshChunkKey, std::shared_ptr<const ReceiverMesh>> chunks_;
  std::map<MeshChunkKey, std::vector<uint32_t>> chunkCells_;  // cells with a piece in each chunk, ascending
};

}  // namespace penumbra
