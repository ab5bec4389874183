#include "core/mesh/mesh_memo.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/illum/face_lookup.h"
#include "core/illum/light_sum.h"
#include "core/mesh/cell_triangulation.h"
#include "core/mesh/fingerprint.h"
#include "core/mesh/lattice_split.h"
#include "core/mesh/receiver_mesh_builder.h"

namespace penumbra {

namespace {

bool sameFrame(const PlaneFrame& a, const PlaneFrame& b) {
  return a.origin == b.origin && a.u == b.u && a.v == b.v && a.normal == b.normal;
}

Vec2 centroid(const Polygon2& polygon) {
  Vec2 middle{0.0};
  for (const Vec2& q : polygon) middle += q;
  return middle / double(polygon.size());
}

}  // namespace

void ReceiverMeshMemo::CellMemo::clearOutput() {
  emitted.clear();
  triangles.clear();
  pieceChunks.clear();
  pieceEmitted.clear();
  pieceTriangles.clear();
}

// One update() call: the cells touched since the last one, then the chunks they changed.
class MeshMemoUpdate {
 public:
  using CellMemo = ReceiverMeshMemo::CellMemo;

  MeshMemoUpdate(ReceiverMeshMemo& memo, const Scene& scene, const MeshSource& source, MeshMemoCounters& counters)
      : memo_(memo), scene_(scene), source_(source), counters_(counters), tree_(source.tree),
        halfEdges_(source.tree.mesh()), eps_(scene.tolerance().length()),
        chunkSide_(memo.grid_.spacing * memo.grid_.chunkSquares),
        dark_(scene.lights().size()) {}

  void run() {
    const uint64_t stamp = HalfEdgeMesh::stampNow();
    for (size_t i = halfEdges_.cellSlots(); i < memo_.cells_.size(); ++i) leaveChunks(uint32_t(i));  // a smaller rebuilt tree
    memo_.cells_.resize(halfEdges_.cellSlots());
    for (uint32_t index = 0; index < halfEdges_.cellSlots(); ++index) updateCell(index);
    memo_.stamp_ = stamp;
    assembleChunks();
    counters_.chunksMeshed += dirty_.size();
    for (const auto& entry : memo_.chunks_) counters_.chunksKept += dirty_.count(entry.first) ? 0 : 1;
  }

 private:
  // Chunks whose cells changed; the memo's old pieces and the new ones both count.
  // A cell's pieces leave or enter the chunks' cell lists (kept in cell order).
  std::set<MeshChunkKey> chunksOf(uint32_t index) const {
    const CellMemo& m = memo_.cells_[index];
    return m.valid ? std::set<MeshChunkKey>(m.pieceChunks.begin(), m.pieceChunks.end()) : std::set<MeshChunkKey>{};
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

  // A point is on a value discontinuity (D0) when an occluder of a cell around it
  // has its plane through it (it touches the receiver there): it then takes its
  // value per side, as the limit from each cell whose list holds such a face (in a
  // cell without one the value is continuous up to the point). "Through it" is the geometric
  // predicate (length tolerance), not onPlane(): a point within onPlane() of the
  // plane but off the contact line (e.g. on a line meeting it at a shallow angle
  // near a footprint corner) lies inside one side, where the value is the point
  // value (the face does not shadow it, SCENE_FORMAT.md), with no other side's
  // copy to carry that value.
  bool onContact(const Vec3& p, const OccluderList& list) const {
    for (const OccluderEntry& entry : list) {
      const Face* face = findFace(scene_, entry.face);
      if (face && std::abs(face->plane.signedDistance(p)) <= eps_) return true;
    }
    return false;
  }
  MeshChunkKey chunkOf(const Polygon2& piece) const {
    if (!(chunkSide_ > 0)) return MeshChunkKey{};
    const Vec2 middle = centroid(piece);
    return MeshChunkKey{int64_t(std::floor(middle.x / chunkSide_)), int64_t(std::floor(middle.y / chunkSide_))};
  }

  // A cell touched since the last call is lit again unless every input is equal.
  void updateCell(uint32_t index) {
    const CellId c(index);
    const HalfEdgeMesh::Cell& cell = halfEdges_.cell(c);
    CellMemo& slot = memo_.cells_[index];
    if (cell.touched <= memo_.stamp_ && (slot.valid || !cell.alive)) {
      if (cell.alive) ++counters_.cellsReused;
      return;
    }
    if (!cell.alive) {
      leaveChunks(index);
      slot = CellMemo{};
      return;
    }
    gatherInputs(c);
    const uint64_t fingerprint = inputs_.fingerprint();
    if (slot.valid && slot.inputs == fingerprint) {
      ++counters_.cellsReused;
      return;
    }
    ++counters_.cellsLit;
    leaveChunks(index);
    output_.clearOutput();
    emitPieces(cell.occluders);
    output_.valid = true;
    output_.inputs = fingerprint;
    std::swap(slot, output_);  // the old slot's buffers are reused for the next cell
    enterChunks(index);
  }

  // What a cell's triangles depend on, gathered for the cell being updated.
  struct CellInputs {
    Polygon2 outline;                     // the cell's loop positions
    OccluderList occluders;               // its list
    std::vector<Vec3> occluderPoints;     // the listed faces' world polygons, concatenated
    std::vector<uint32_t> occluderSizes;  // their vertex counts (0: not a scene face)
    // Per loop corner: 1 if lit from the cell (a face of its list through it), else 0 and its value.
    std::vector<uint8_t> cornerFromCell;
    std::vector<VertexIrradiance> cornerValues;
    void clear() {
      outline.clear();
      occluders.clear();
      occluderPoints.clear();
      occluderSizes.clear();
      cornerFromCell.clear();
      cornerValues.clear();
    }
    uint64_t fingerprint() const {
      Fingerprint f;
      f.addBytes(std::span<const Vec2>(outline));
      f.add(uint64_t(occluders.size()));
      for (const OccluderEntry& e : occluders) {
        f.add(uint64_t(e.light) << 1 | uint64_t(e.umbra));
        f.add(uint64_t(e.face.object) << 32 | uint64_t(e.face.face));
      }
      f.addBytes(std::span<const Vec3>(occluderPoints));
      f.addBytes(std::span<const uint32_t>(occluderSizes));
      f.addBytes(std::span<const uint8_t>(cornerFromCell));
      f.add(uint64_t(cornerValues.size()));
      for (const VertexIrradiance& v : cornerValues) {
        for (int c = 0; c < 3; ++c) f.add(v.irradiance[c]);
        f.add(uint64_t(v.lightClass));
      }
      return f.value();
    }
  };

  // The inputs this cell's triangles depend on, into inputs_ (dark_ and anyDark_ too).
  void gatherInputs(CellId c) {
    const OccluderList& list = halfEdges_.cell(c).occluders;
    std::fill(dark_.begin(), dark_.end(), false);
    for (const OccluderEntry& entry : list)
      if (entry.umbra) dark_[entry.light] = true;
    const bool anyDark = std::find(dark_.begin(), dark_.end(), true) != dark_.end();
    inputs_.clear();
    corners_.clear();
    for (HalfEdgeId h : halfEdges_.loop(c)) corners_.push_back(halfEdges_.halfEdge(h).origin);
    for (VertexId v : corners_) inputs_.outline.push_back(tree_.position(v));
    inputs_.occluders = list;
    for (const OccluderEntry& entry : list) {
      const Face* face = findFace(scene_, entry.face);
      inputs_.occluderSizes.push_back(face ? uint32_t(face->polygon.size()) : 0);
      if (face) inputs_.occluderPoints.insert(inputs_.occluderPoints.end(), face->polygon.begin(), face->polygon.end());
    }
    for (VertexId v : corners_) {
      // Only a face of this cell's list can hide light from the cell and not from the
      // corner (it passes through the corner); with none, the corner's value is the limit.
      const bool fromCell = onContact(source_.frame.to3D(tree_.position(v)), list);
      inputs_.cornerFromCell.push_back(fromCell ? 1 : 0);
      inputs_.cornerValues.push_back(fromCell ? VertexIrradiance{}
                                     : anyDark ? sumLights(scene_, source_.perLight[v.index], &dark_)
                                               : source_.values[v.index]);
    }
  }

  // The value of a point of the cell's closure, as seen from the cell (centre: its centroid).
  // A point lit here is kept for the cell: a lattice point is a corner of up to four of its
  // pieces, and the same inputs give the same bits, so it is lit once.
  VertexIrradiance valueAt(const Vec2& q, const OccluderList& list, const Vec3& centre) {
    const Polygon2& polygon = inputs_.outline;
    const size_t corner = size_t(std::find(polygon.begin(), polygon.end(), q) - polygon.begin());
    if (corner < polygon.size() && !inputs_.cornerFromCell[corner]) return inputs_.cornerValues[corner];
    for (const auto& [at, value] : litInCell_)
      if (at == q) return value;
    const Vec3 p = source_.frame.to3D(q);
    const Vec3 normal = source_.frame.normal;
    // A contact corner or lattice point takes the limit from the cell; another lattice
    // point is lit exactly from this cell's list (cases 2 and 3 keep it dark in a light's umbra).
    const VertexIrradiance value = corner < polygon.size() || onContact(p, list)
                                       ? illuminatePointFromCell(scene_, p, normal, centre - p, list)
                                       : illuminatePoint(scene_, p, normal, {&list});
    litInCell_.push_back({q, value});
    return value;
  }

  // The cell's pieces (lattice squares' parts), triangulated, into output_.
  void emitPieces(const OccluderList& list) {
    const Polygon2& polygon = inputs_.outline;
    Vec3 centre{0.0};
    for (const Vec2& q : polygon) centre += source_.frame.to3D(q);
    centre /= double(polygon.size());
    litInCell_.clear();
    for (const Polygon2& piece : splitByLattice(polygon, memo_.grid_.spacing, eps_)) {
      output_.pieceChunks.push_back(chunkOf(piece));
      output_.pieceEmitted.push_back(uint32_t(output_.emitted.size()));
      output_.pieceTriangles.push_back(uint32_t(output_.triangles.size()));
      std::vector<uint32_t> pieceCorners;
      for (const Vec2& q : piece) {
        pieceCorners.push_back(uint32_t(output_.emitted.size()));
        output_.emitted.push_back({q, valueAt(q, list, centre)});
      }
      const CellTriangulation triangulation = triangulateConvexCell(piece, eps_);
      if (triangulation.usesCentre) {
        const Vec2 middle = centroid(piece);
        pieceCorners.push_back(uint32_t(output_.emitted.size()));
        output_.emitted.push_back(
            {middle, illuminatePoint(scene_, source_.frame.to3D(middle), source_.frame.normal, {&list})});
      }
      for (const auto& t : triangulation.triangles)
        output_.triangles.push_back({pieceCorners[t[0]], pieceCorners[t[1]], pieceCorners[t[2]]});
    }
    output_.pieceEmitted.push_back(uint32_t(output_.emitted.size()));
    output_.pieceTriangles.push_back(uint32_t(output_.triangles.size()));
  }

  // The changed chunks are assembled again from their cells' pieces, in cell order;
  // the builder sees the same calls in the same order as for a fresh mesh.
  void assembleChunks() {
    std::vector<uint32_t> ids;
    for (const MeshChunkKey& key : dirty_) {
      ReceiverMesh mesh;
      mesh.face = source_.face;
      mesh.normal = source_.frame.normal;
      ReceiverMeshBuilder builder(mesh, source_.frame, eps_);
      auto listed = memo_.chunkCells_.find(key);
      if (listed != memo_.chunkCells_.end())
        for (uint32_t index : listed->second) {
          const CellMemo& m = memo_.cells_[index];
          for (size_t j = 0; j < m.pieceChunks.size(); ++j) {
            if (m.pieceChunks[j] != key) continue;
            ids.resize(m.emitted.size());
            for (uint32_t e = m.pieceEmitted[j]; e < m.pieceEmitted[j + 1]; ++e)
              ids[e] = builder.vertex(m.emitted[e].first, m.emitted[e].second);
            for (uint32_t t = m.pieceTriangles[j]; t < m.pieceTriangles[j + 1]; ++t)
              mesh.triangles.push_back({ids[m.triangles[t][0]], ids[m.triangles[t][1]], ids[m.triangles[t][2]]});
          }
        }
      if (listed != memo_.chunkCells_.end() && listed->second.empty()) memo_.chunkCells_.erase(listed);
      if (mesh.triangles.empty())
        memo_.chunks_.erase(key);
      else
        memo_.chunks_[key] = std::make_shared<const ReceiverMesh>(std::move(mesh));
    }
  }

  ReceiverMeshMemo& memo_;
  const Scene& scene_;
  const MeshSource& source_;
  MeshMemoCounters& counters_;
  const DmTree& tree_;
  const HalfEdgeMesh& halfEdges_;
  const double eps_, chunkSide_;  // chunkSide_ 0: one chunk
  std::set<MeshChunkKey> dirty_;
  CellInputs inputs_;  // the current cell's inputs
  CellMemo output_;    // its output when lit afresh, swapped into the memo
  std::vector<bool> dark_;
  std::vector<VertexId> corners_;
  std::vector<std::pair<Vec2, VertexIrradiance>> litInCell_;  // points lit for the current cell
};

void ReceiverMeshMemo::update(const Scene& scene, const MeshSource& source, MeshGrid grid, MeshMemoCounters& counters) {
  // The memo is only valid for the same face frame, lattice, chunks and tolerance.
  const double eps = scene.tolerance().length();
  if (!sameFrame(frame_, source.frame) || grid_.spacing != grid.spacing || eps_ != eps ||
      grid_.chunkSquares != grid.chunkSquares) {
    *this = ReceiverMeshMemo{};
    frame_ = source.frame;
    grid_ = grid;
    eps_ = eps;
  }
  MeshMemoUpdate(*this, scene, source, counters).run();
}

}  // namespace penumbra
