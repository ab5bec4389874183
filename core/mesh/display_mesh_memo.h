// The display mesh of every receiver of one engine, kept between mesh calls: per receiving
// face, a ReceiverMeshMemo (receiver_mesh_memo.h: its cells and chunks) or, where the source
// says so (MeshSource::fromLattice), a LatticeMeshMemo (its lattice squares), and what the last
// call did. Owned by one engine, which hands in its receivers as MeshSources; one writer at a
// time, const reads from several threads are safe.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "core/mesh/cell_lighting.h"
#include "core/mesh/lattice_mesh_memo.h"
#include "core/mesh/mesh.h"
#include "core/mesh/receiver_mesh_memo.h"
#include "core/util/parallel.h"
#include "core/util/shared_progress.h"

namespace penumbra {

class DisplayMeshMemo {
 public:
  // Brings the listed receivers' memos up to date with their sources (each face once), on
  // `parallel`'s threads: receivers in parallel, and each one's cells. The counters of this call
  // replace the last call's (summed in `sources` order). progress: step "triangulation", counting
  // the receivers' cells (lattice squares where meshed from the lattice). Each receiver's memo
  // kind is chosen afresh (the other kind's memo is dropped).
  void update(const Scene& scene, const std::vector<MeshSource>& sources, const MeshGrid& grid,
              const Parallel& parallel, const StepProgress& progress = {});
  // The up-to-date memos of `sources` as one Mesh, in that order: each receiver's chunks
  // concatenated, with the cells capped short of `tolerance` counted.
  Mesh assemble(const std::vector<MeshSource>& sources, double tolerance) const;
  // One receiver's up-to-date memo as one mesh. Throws std::out_of_range if never updated.
  ReceiverMesh meshOf(const MeshSource& source) const;
  // One receiver's chunks, in key order. Throws std::out_of_range if never updated.
  const std::map<MeshChunkKey, std::shared_ptr<const ReceiverMesh>>& chunksOf(FaceId face) const;
  // Whether the receiver's last update meshed it from its lattice squares (false if never).
  bool fromLattice(FaceId face) const {
    const auto it = receivers_.find(face);
    return it != receivers_.end() && it->second.lattice;
  }
  // Drops the memos of faces that are no longer receivers.
  void keepOnly(const std::function<bool(FaceId)>& isReceiver);
  // Drops one receiver's memo (its tree was cast afresh), or all: the next update lights every
  // cell of those receivers afresh.
  void forget(FaceId face) { receivers_.erase(face); }
  void clear() { receivers_.clear(); }
  // What the last update did: cells kept / lit afresh, chunks assembled again / kept.
  const MeshMemoCounters& lastCounters() const { return counters_; }

 private:
  // One receiver's memo: of its cells, or (lattice) of its lattice squares.
  struct ReceiverMemo {
    bool lattice = false;
    ReceiverMeshMemo cells;
    LatticeMeshMemo squares;
    const std::map<MeshChunkKey, std::shared_ptr<const ReceiverMesh>>& chunks() const {
      return lattice ? squares.chunks() : cells.chunks();
    }
    size_t capped() const { return lattice ? squares.cappedSquares() : cells.cappedCells(); }
  };
  std::map<FaceId, ReceiverMemo> receivers_;
  MeshMemoCounters counters_;
};

}  // namespace penumbra
