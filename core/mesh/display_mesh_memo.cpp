#include "core/mesh/display_mesh_memo.h"

namespace penumbra {

void DisplayMeshMemo::update(const Scene& scene, const std::vector<MeshSource>& sources,
                             const MeshGrid& grid, const Parallel& parallel,
                             const StepProgress& progress) {
  counters_ = {};
  std::vector<ReceiverMemo*> memos;  // created here: the map is not changed in parallel
  // Counted in cells (squares for a receiver meshed from its lattice), all known before any is
  // lit: one receiver, the floor of a dense room or under a model, may hold most of them.
  size_t units = 0;
  for (const MeshSource& source : sources) {
    ReceiverMemo& memo = receivers_[source.face];
    if (source.fromLattice != memo.lattice) {
      memo = ReceiverMemo{};
      memo.lattice = source.fromLattice;
    }
    units += memo.lattice ? memo.squares.units(scene, source, grid) : ReceiverMeshMemo::units(source);
    memos.push_back(&memo);
  }
  SharedProgress report(progress, "triangulation", units, ReceiverMeshMemo::kCellsPerReport);
  std::vector<MeshMemoCounters> counters(sources.size());
  const MeshProgress counted =
      progress ? MeshProgress([&](size_t done) { done ? report.add(done) : report.beat(); }) : nullptr;
  parallel.forEach(sources.size(), [&](size_t k) {
    ReceiverMemo& memo = *memos[k];
    if (memo.lattice)
      memo.squares.update(scene, sources[k], grid, counters[k], parallel, counted);
    else
      memo.cells.update(scene, sources[k], grid, counters[k], parallel, counted);
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
