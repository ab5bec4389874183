#include "core/mesh/receiver_mesh_memo.h"

#include <algorithm>
#include <set>

#include "core/illum/light_sum.h"
#include "core/mesh/receiver_mesh_builder.h"

namespace penumbra {

namespace {

void shrinkToFit(ReceiverMesh& mesh) {
  mesh.positions.shrink_to_fit();
  mesh.irradiance.shrink_to_fit();
  mesh.classes.shrink_to_fit();
  mesh.triangles.shrink_to_fit();
}

}  // namespace

// One update() call: the cells touched since the last one, then the chunks they changed.
class MeshMemoUpdate {
 public:
  MeshMemoUpdate(ReceiverMeshMemo& memo, const Scene& scene, const MeshSource& source, MeshMemoCounters& counters,
                 const MeshProgress& progress)
      : memo_(memo), scene_(scene), source_(source), counters_(counters), halfEdges_(source.tree.mesh()),
        eps_(scene.tolerance().length()), chunkSide_(memo.grid_.spacing * memo.grid_.chunkSquares), progress_(progress) {}

  void run(const Parallel& parallel) {
    const uint64_t stamp = HalfEdgeMesh::stampNow();
    for (size_t i = halfEdges_.cellSlots(); i < memo_.cells_.size(); ++i) leaveChunks(uint32_t(i));  // a smaller rebuilt tree
    memo_.cells_.resize(halfEdges_.cellSlots());
    std::vector<uint32_t> touched;
    for (uint32_t index = 0; index < halfEdges_.cellSlots(); ++index)
      if (needsLight(index)) touched.push_back(index);
    if (progress_) progress_(halfEdges_.cellSlots() - touched.size());  // nothing to light there
    lightCells(touched, parallel);
    memo_.stamp_ = stamp;
    // Cells keep each light's value; chunks hold their sum: a new radiance changes them all.
    std::vector<Vec3> radiance;
    for (const Light& light : scene_.lights()) radiance.push_back(light.radiance);
    if (radiance != memo_.radiance_)
      for (const auto& entry : memo_.chunkCells_) dirty_.insert(entry.first);
    memo_.radiance_ = std::move(radiance);
    assembleChunks(parallel);
    counters_.chunksMeshed += dirty_.size();
    for (const auto& entry : memo_.chunks_) counters_.chunksKept += dirty_.count(entry.first) ? 0 : 1;
  }

 private:
  // Chunks whose cells changed; the memo's old pieces and the new ones both count.
  // A cell's pieces leave or enter the chunks' cell lists (kept in cell order).
  std::set<MeshChunkKey> chunksOf(uint32_t index) const {
    const CellMemo& m = memo_.cells_[index];
    std::set<MeshChunkKey> keys;
    if (m.valid())
      for (size_t i = 0; i < m.pieceCount(); ++i) keys.insert(m.piece(i).chunk);
    return keys;
  }
  void leaveChunks(uint32_t index) {
    for (const MeshChunkKey& key : chunksOf(index)) {
      dirty_.insert(key);
      std::vector<uint32_t>& cells = memo_.chunkCells_[key];
      const auto at = std::lower_bound(cells.begin(), cells.end(), index);
      if (at != cells.end() && *at == index) cells.erase(at);
    }
  }
  void enterChunks(uint32_t index) {
    for (const MeshChunkKey& key : chunksOf(index)) {
      dirty_.insert(key);
      std::vector<uint32_t>& cells = memo_.chunkCells_[key];
      cells.insert(std::lower_bound(cells.begin(), cells.end(), index), index);
    }
  }

  // A live cell touched since the last call may need lighting; a dead one leaves its chunks.
  bool needsLight(uint32_t index) {
    const HalfEdgeMesh::Cell& cell = halfEdges_.cell(CellId(index));
    CellMemo& slot = memo_.cells_[index];
    if (cell.touched() <= memo_.stamp_ && (slot.valid() || !cell.alive)) {
      if (cell.alive) ++counters_.cellsReused;
      return false;
    }
    if (cell.alive) return true;
    leaveChunks(index);
    slot = CellMemo{};
    return false;
  }

  // The touched cells are lit in blocks on the threads, each into its own result (kept
  // when its fingerprint equals the slot's); then, in cell order, the results replace
  // the slots and enter their chunks.
  void lightCells(const std::vector<uint32_t>& touched, const Parallel& parallel) {
    constexpr size_t kBlock = 64;
    std::vector<CellMemo> results(touched.size());
    const double spacing = memo_.grid_.spacing;
    SharedPointValues shared(source_.perLight.lightCount());
    std::vector<MeshMemoCounters> blocks((touched.size() + kBlock - 1) / kBlock);
    parallel.forEach(blocks.size(), [&](size_t block) {
      CellLighter lighter(scene_, source_, spacing, chunkSide_, memo_.grid_.refine, &shared);
      for (size_t k = block * kBlock; k < std::min(touched.size(), (block + 1) * kBlock); ++k) {
        if (progress_ && k % ReceiverMeshMemo::kCellsPerReport == 0)
          progress_(std::min(ReceiverMeshMemo::kCellsPerReport, touched.size() - k));
        const CellId c(touched[k]);
        const uint64_t fingerprint = lighter.gather(c);
        const CellMemo& slot = memo_.cells_[touched[k]];
        if (slot.valid() && slot.inputs() == fingerprint) continue;  // results[k] stays invalid: kept
        lighter.emit(c, results[k]);
      }
      blocks[block].testPoints = lighter.testPoints(), blocks[block].testPointsKept = lighter.testPointsKept();
    });
    for (const MeshMemoCounters& b : blocks) counters_ += b;
    for (size_t k = 0; k < touched.size(); ++k) {
      if (!results[k].valid()) {
        ++counters_.cellsReused;
        continue;
      }
      ++counters_.cellsLit;
      leaveChunks(touched[k]);
      memo_.cells_[touched[k]] = std::move(results[k]);
      enterChunks(touched[k]);
    }
  }

  // The changed chunks are assembled again from their cells' pieces, in cell order;
  // the builder sees the same calls in the same order as for a fresh mesh. Chunks are
  // independent: built on the threads, stored in key order.
  void assembleChunks(const Parallel& parallel) {
    const std::vector<MeshChunkKey> keys(dirty_.begin(), dirty_.end());
    std::vector<ReceiverMesh> meshes(keys.size());
    parallel.forEach(keys.size(), [&](size_t k) {
      if (progress_) progress_(0);
      assembleChunk(keys[k], meshes[k]);
      shrinkToFit(meshes[k]);  // kept until the chunk changes: growth's spare room was ~20 % of it
    });
    for (size_t k = 0; k < keys.size(); ++k) {
      const auto listed = memo_.chunkCells_.find(keys[k]);
      if (listed != memo_.chunkCells_.end() && listed->second.empty()) memo_.chunkCells_.erase(listed);
      if (meshes[k].triangles.empty())
        memo_.chunks_.erase(keys[k]);
      else
        memo_.chunks_[keys[k]] = std::make_shared<const ReceiverMesh>(std::move(meshes[k]));
    }
  }
  void assembleChunk(const MeshChunkKey& key, ReceiverMesh& mesh) const {
    mesh.face = source_.face;
    mesh.normal = source_.frame.normal;
    ReceiverMeshBuilder builder(mesh, source_.frame, eps_);
    const auto listed = memo_.chunkCells_.find(key);
    if (listed == memo_.chunkCells_.end()) return;
    std::vector<uint32_t> ids;
    std::vector<bool> dark(scene_.lights().size());
    for (uint32_t index : listed->second) {
      const CellMemo& m = memo_.cells_[index];
      ids.resize(m.pointCount());
      const bool anyDark = darkLights(halfEdges_.occluders(CellId(index)), dark);
      uint32_t pointsBegin = 0, listedBegin = 0;
      for (size_t i = 0; i < m.pieceCount(); ++i) {
        const CellMemo::Piece piece = m.piece(i);
        if (piece.chunk == key) {
          for (uint32_t e = pointsBegin; e < piece.pointsEnd; ++e) ids[e] = vertexOf(m, m.point(e), dark, anyDark, builder);
          const auto add = [&](const std::array<uint32_t, 3>& corners) {
            mesh.triangles.push_back(
                {ids[pointsBegin + corners[0]], ids[pointsBegin + corners[1]], ids[pointsBegin + corners[2]]});
          };
          if (piece.fan.listed()) {
            for (uint32_t t = listedBegin; t < piece.fan.listedEnd(); ++t) add(m.listedTriangle(t));
          } else {
            const uint32_t loop = piece.pointsEnd - pointsBegin - (piece.fan.usesCentre() ? 1 : 0);
            for (uint32_t t = 0; t < piece.fan.triangleCount(loop); ++t) add(piece.fan.triangle(loop, t));
          }
        }
        pointsBegin = piece.pointsEnd;
        if (piece.fan.listed()) listedBegin = piece.fan.listedEnd();
      }
    }
  }
  // One emitted point handed to the builder: a corner's vertex, as the cell sees it (dark: its
  // lights in umbra), or the copy kept.
  uint32_t vertexOf(const CellMemo& m, uint32_t point, const std::vector<bool>& dark, bool anyDark,
                    ReceiverMeshBuilder& builder) const {
    if (point & CellMemo::kOwnValue) {
      thread_local std::vector<VertexLight> row;
      m.ownLights(point & CellMemo::kIndexMask, row);
      return builder.vertex(m.ownAt(point & CellMemo::kIndexMask), sumLights(scene_, row));
    }
    const VertexId v(point & CellMemo::kIndexMask);
    return builder.vertex(source_.tree.position(v),
                          cornerValue(scene_, source_, v, dark, (point & CellMemo::kDarkCorner) != 0 && anyDark));
  }

  ReceiverMeshMemo& memo_;
  const Scene& scene_;
  const MeshSource& source_;
  MeshMemoCounters& counters_;
  const HalfEdgeMesh& halfEdges_;
  const double eps_, chunkSide_;  // chunkSide_ 0: one chunk
  const MeshProgress& progress_;
  std::set<MeshChunkKey> dirty_;
};

void ReceiverMeshMemo::update(const Scene& scene, const MeshSource& source, MeshGrid grid, MeshMemoCounters& counters,
                              const Parallel& parallel, const MeshProgress& progress) {
  // The memo is only valid for the same face frame, lattice, chunks and tolerance.
  const double eps = scene.tolerance().length();
  if (frame_ != source.frame || grid_ != grid || eps_ != eps) {
    *this = ReceiverMeshMemo{};
    frame_ = source.frame;
    grid_ = grid;
    eps_ = eps;
  }
  MeshMemoUpdate(*this, scene, source, counters, progress).run(parallel);
}

size_t ReceiverMeshMemo::cappedCells() const {
  return size_t(std::count_if(cells_.begin(), cells_.end(), [](const CellMemo& m) { return m.capped(); }));
}

}  // namespace penumbra
