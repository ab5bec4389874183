#include "core/mesh/display_mesh_memo.h"

namespace penumbra {

void DisplayMeshMemo::update(const Scene& scene, const std::vector<MeshSource>& sources,
                             const MeshGrid& grid, const Parallel& parallel,
                             const StepProgress& progress) {
  counters_ = {};
  SharedProgress report(progress, "triangulation", sources.size(), 1);
  std::vector<ReceiverMemo*> memos;  // created here: the map is not changed in parallel
  for (const MeshSource& source : sources) memos.push_back(&receivers_[source.face]);
  std::vector<MeshMemoCounters> counters(sources.size());
  // Beats from inside a receiver's meshing: the floor of a dense scene is most of it.
  const std::function<void()> beat = progress ? std::function<void()>([&] { report.beat(); }) : nullptr;
  parallel.forEach(sources.size(), [&](size_t k) {
    ReceiverMemo& memo = *memos[k];
    const bool lattice = sources[k].fromLattice;
    if (lattice != memo.lattice) {
      memo = ReceiverMemo{};
      memo.lattice = lattice;
    }
    if (lattice)
      memo.squares.update(scene, sources[k], grid, counters[k], parallel, beat);
    else
      memo.cells.update(scene, sources[k], grid, counters[k], parallel, beat);
    report.add(1);
  });
  report.finish();
  for (const MeshMemoCounters& c : counters) counters_ += c;
}

Mesh DisplayMeshMemo::assemble(const std::vector<MeshSource>& sources, double tolerance) const {
  Mesh out;
  out.tolerance = tolerance;
  out.receivers.reserve(sources.size());
  for (const MeshSource& source : sources) {
    out.receivers.push_back(meshOf(source));
    out.cappedCells += receivers_.at(source.face).capped();
  }
  return out;
}

ReceiverMesh DisplayMeshMemo::meshOf(const MeshSource& source) const {
  const auto& chunks = chunksOf(source.face);
  ReceiverMesh result;
  result.face = source.face;
  result.normal = source.frame.normal;
  size_t vertices = 0, triangles = 0;  // reserved at once: growth would leave up to half spare
  for (const auto& [key, chunk] : chunks) {
    vertices += chunk->positions.size();
    triangles += chunk->triangles.size();
  }
  result.positions.reserve(vertices);
  result.irradiance.reserve(vertices);
  result.classes.reserve(vertices);
  result.triangles.reserve(triangles);
  for (const auto& [key, chunk] : chunks) appendMesh(result, *chunk);
  return result;
}

const std::map<MeshChunkKey, std::shared_ptr<const ReceiverMesh>>& DisplayMeshMemo::chunksOf(
    FaceId face) const {
  return receivers_.at(face).chunks();
}

void DisplayMeshMemo::keepOnly(const std::function<bool(FaceId)>& isReceiver) {
  for (auto it = receivers_.begin(); it != receivers_.end();)
    it = isReceiver(it->first) ? std::next(it) : receivers_.erase(it);
}

}  // namespace penumbra
