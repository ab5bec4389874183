// The display mesh of every receiver of one engine, kept between mesh calls: one
// ReceiverMeshMemo (receiver_mesh_memo.h: its cells and chunks) per receiving face, and what the
// last call did. Owned by one engine, which hands in its receivers as MeshSources; one writer at a
// time, const reads from several threads are safe.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "core/mesh/cell_lighting.h"
#include "core/mesh/mesh.h"
#include "core/mesh/receiver_mesh_memo.h"
#include "core/util/parallel.h"
#include "core/util/shared_progress.h"

namespace penumbra {

class DisplayMeshMemo {
 public:
  // Brings the listed receivers' memos up to date with their sources (each face once), on
  // `parallel`'s threads: receivers in parallel, and each one's cells. The counters of this call
  // replace the last call's (summed in `sources` order). progress: step "triangulation", per
  // receiver.
  void update(const Scene& scene, const std::vector<MeshSource>& sources, const MeshGrid& grid,
              const Parallel& parallel, const StepProgress& progress = {});
  // The up-to-date memos of `sources` as one Mesh, in that order: each receiver's chunks
  // concatenated, with the cells capped short of `tolerance` counted.
  Mesh assemble(const std::vector<MeshSource>& sources, double tolerance) const;
  // One receiver's up-to-date memo as one mesh. Throws std::out_of_range if never updated.
  ReceiverMesh meshOf(const MeshSource& source) const;
  // One receiver's chunks, in key order. Throws std::out_of_range if never updated.
  const std::map<MeshChunkKey, std::shared_ptr<const ReceiverMesh>>& chunksOf(FaceId face) const;
  // Drops the memos of faces that are no longer receivers.
  void keepOnly(const std::function<bool(FaceId)>& isReceiver);
  // Drops one receiver's memo (its tree was cast afresh), or all: the next update lights every
  // cell of those receivers afresh.
  void forget(FaceId face) { receivers_.erase(face); }
  void clear() { receivers_.clear(); }
  // What the last update did: cells kept / lit afresh, chunks assembled again / kept.
  const MeshMemoCounters& lastCounters() const { return counters_; }

 private:
  std::map<FaceId, ReceiverMeshMemo> receivers_;
  MeshMemoCounters counters_;
};

}  // namespace penumbra
