#include "core/mesh/lattice_mesh_memo.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>

#include "core/geom/convex2d.h"
#include "core/illum/backprojection.h"
#include "core/illum/face_lookup.h"
#include "core/illum/light_sum.h"
#include "core/mesh/cell_refinement.h"
#include "core/mesh/cell_triangulation.h"
#include "core/mesh/lattice_split.h"
#include "core/mesh/receiver_mesh_builder.h"
#include "core/mesh/shared_point_values.h"

namespace penumbra {

namespace {

template <class T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Lights the points of one receiver's squares, each from the DM-tree cell holding it (a flat
// face with no contact: the value is continuous, so either cell of a point on a cell edge gives
// it). One per thread.
class SquareLighter {
 public:
  SquareLighter(const Scene& scene, const MeshSource& source, const RefineSettings& refine, double spacing,
                SharedPointValues& shared)
      : scene_(scene), source_(source), refine_(refine), spacing_(spacing), eps_(scene.tolerance().length()),
        shared_(shared) {}

  // Refinement's test points of every light() so far.
  const MeshMemoCounters& counted() const { return counted_; }

  void light(const Polygon2& outline, LatticeMeshMemo::Square& out) {
    PieceRefinement& r = refinement_;
    r.lights = source_.perLight.lightCount();
    r.points.assign(outline.begin(), outline.end());
    r.values.clear(), r.levels.clear(), r.triangles.clear();
    r.capped = false;
    const CellFan fan = fanOfConvexCell(outline, eps_);
    if (fan.usesCentre()) r.points.push_back(vertexAverage(outline));
    for (const Vec2& q : r.points) valuesAt(q, r.values);
    const uint32_t loop = uint32_t(outline.size());
    for (uint32_t t = 0; t < fan.triangleCount(loop); ++t) r.triangles.push_back(fan.triangle(loop, t));
    if (refine_.tolerance > 0 && !narrowerThan(outline, refine_.minEdge)) {
      const size_t before = r.points.size();
      refinePiece(
          r, refine_, [&](const Vec2& q, std::vector<VertexLight>& values) { valuesAt(q, values); },
          [&](const Vec2& q, std::vector<double>& levels) { levelsAt(q, levels); });
      counted_.testPoints += r.asked, counted_.testPointsKept += r.points.size() - before;
    }
    out.points = r.points;
    out.lights = r.values;
    out.triangles = r.triangles;
    out.capped = r.capped;
  }

 private:
  void valuesAt(const Vec2& q, std::vector<VertexLight>& out) {
    const OccluderList& list = source_.tree.occluders(source_.tree.locate(q));
    // A point on a lattice line is asked by the square on its other side too.
    const bool shareable = onLattice(q);
    if (shareable && shared_.find(q, &list, out)) return;
    const size_t first = out.size();
    const Vec3 p = source_.frame.to3D(q), n = source_.frame.normal;
    oneCell_.assign(1, &list);
    for (size_t l = 0; l < source_.perLight.lightCount(); ++l) out.push_back(illuminateVertex(scene_, l, p, n, n, oneCell_));
    if (shareable) shared_.keep(q, &list, std::span(out).subspan(first));
  }
  void levelsAt(const Vec2& q, std::vector<double>& out) const {
    thread_local Backprojection view;
    const Vec3 p = source_.frame.to3D(q), n = source_.frame.normal;
    for (size_t l = 0; l < source_.perLight.lightCount(); ++l) {
      view.reset(scene_, l, p, n, n);
      out.push_back(view.applies() ? view.unoccludedFactor() : 0.0);
    }
  }
  bool onLattice(const Vec2& q) const {
    const auto near = [&](double x) { return std::abs(x - std::round(x / spacing_) * spacing_) <= eps_; };
    return near(q.x) || near(q.y);
  }

  const Scene& scene_;
  const MeshSource& source_;
  const RefineSettings refine_;
  const double spacing_, eps_;
  SharedPointValues& shared_;
  PieceRefinement refinement_;
  std::vector<const OccluderList*> oneCell_;
  MeshMemoCounters counted_;  // refinement's test points only
};

}  // namespace

bool LatticeMeshMemo::Square::sameAs(const Square& other) const {
  return capped == other.capped && sameBytes(points, other.points) && sameBytes(lights, other.lights) &&
         sameBytes(triangles, other.triangles);
}

void LatticeMeshMemo::reset(const Scene& scene, const MeshSource& source, const MeshGrid& grid) {
  *this = LatticeMeshMemo{};
  frame_ = source.frame;
  grid_ = grid;
  eps_ = scene.tolerance().length();
  const Face* face = findFace(scene, source.face);
  if (!face) return;
  Polygon2 outline;
  for (const Vec3& v : face->polygon) outline.push_back(source.frame.to2D(v));
  if (signedArea(outline) < 0) std::reverse(outline.begin(), outline.end());
  outlines_ = splitByLattice(outline, grid.spacing, eps_);
  const double chunkSide = grid.spacing * grid.chunkSquares;
  for (uint32_t s = 0; s < outlines_.size(); ++s) {
    const Vec2 middle = vertexAverage(outlines_[s]);
    chunkOf_.push_back(chunkSide > 0 ? MeshChunkKey{int64_t(std::floor(middle.x / chunkSide)),
                                                    int64_t(std::floor(middle.y / chunkSide))}
                                     : MeshChunkKey{});
    squaresAt_[{int64_t(std::floor(middle.x / grid.spacing)), int64_t(std::floor(middle.y / grid.spacing))}].push_back(s);
  }
  squares_.resize(outlines_.size());
}

std::vector<uint32_t> LatticeMeshMemo::touchedSquares(const MeshSource& source) const {
  std::vector<uint32_t> out;
  if (fresh_) {
    for (uint32_t s = 0; s < outlines_.size(); ++s) out.push_back(s);
    return out;
  }
  const HalfEdgeMesh& halfEdges = source.tree.mesh();
  std::set<std::pair<int64_t, int64_t>> indices;
  for (uint32_t index = 0; index < halfEdges.cellSlots(); ++index) {
    const HalfEdgeMesh::Cell& cell = halfEdges.cell(CellId(index));
    // A dead cell's area is held by live cells touched when it died (cells tile the face).
    if (!cell.alive || cell.touched() <= stamp_) continue;
    Vec2 low(INFINITY), high(-INFINITY);
    for (HalfEdgeId h : halfEdges.loop(CellId(index))) {
      const Vec2 q = halfEdges.vertex(halfEdges.halfEdge(h).origin).position;
      low = glm::min(low, q), high = glm::max(high, q);
    }
    // Squares within eps of the cell: a point on their common line may lie in it.
    for (int64_t x = int64_t(std::floor((low.x - eps_) / grid_.spacing)); x <= int64_t(std::floor((high.x + eps_) / grid_.spacing)); ++x)
      for (int64_t y = int64_t(std::floor((low.y - eps_) / grid_.spacing)); y <= int64_t(std::floor((high.y + eps_) / grid_.spacing)); ++y)
        indices.insert({x, y});
  }
  for (const auto& index : indices)
    if (const auto it = squaresAt_.find(index); it != squaresAt_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
  std::sort(out.begin(), out.end());
  return out;
}

size_t LatticeMeshMemo::units(const Scene& scene, const MeshSource& source, MeshGrid grid) {
  grid.refine.tolerance = grid.latticeTolerance * kToleranceShare;
  const double eps = scene.tolerance().length();
  if (frame_ != source.frame || grid_ != grid || eps_ != eps) reset(scene, source, grid);
  return squares_.size();
}

void LatticeMeshMemo::update(const Scene& scene, const MeshSource& source, MeshGrid grid, MeshMemoCounters& counters,
                             const Parallel& parallel, const MeshProgress& progress) {
  units(scene, source, grid);  // the memo fits these arguments from here on
  const uint64_t stamp = HalfEdgeMesh::stampNow();
  const std::vector<uint32_t> touched = touchedSquares(source);
  counters.cellsReused += squares_.size() - touched.size();
  if (progress) progress(squares_.size() - touched.size());  // nothing to light there

  // Touched squares lit on the threads, each into its own slot; kept where nothing changed.
  std::vector<Square> results(touched.size());
  SharedPointValues shared(source.perLight.lightCount());
  constexpr size_t kBlock = 16;
  std::vector<MeshMemoCounters> blocks((touched.size() + kBlock - 1) / kBlock);
  parallel.forEach(blocks.size(), [&](size_t block) {
    SquareLighter lighter(scene, source, grid_.refine, grid_.spacing, shared);
    for (size_t k = block * kBlock; k < std::min(touched.size(), (block + 1) * kBlock); ++k) {
      if (progress) progress(1);
      lighter.light(outlines_[touched[k]], results[k]);
    }
    blocks[block] = lighter.counted();
  });
  for (const MeshMemoCounters& b : blocks) counters += b;
  std::set<MeshChunkKey> dirty;
  for (size_t k = 0; k < touched.size(); ++k) {
    Square& slot = squares_[touched[k]];
    if (!fresh_ && slot.sameAs(results[k])) {
      ++counters.cellsReused;
      continue;
    }
    ++counters.cellsLit;
    slot = std::move(results[k]);
    dirty.insert(chunkOf_[touched[k]]);
  }
  if (fresh_)
    for (uint32_t s = 0; s < squares_.size(); ++s) chunkSquares_[chunkOf_[s]].push_back(s);
  fresh_ = false;
  stamp_ = stamp;
  std::vector<Vec3> radiance;
  for (const Light& light : scene.lights()) radiance.push_back(light.radiance);
  if (radiance != radiance_)
    for (const auto& entry : chunkSquares_) dirty.insert(entry.first);
  radiance_ = std::move(radiance);

  const std::vector<MeshChunkKey> keys(dirty.begin(), dirty.end());
  std::vector<ReceiverMesh> meshes(keys.size());
  parallel.forEach(keys.size(), [&](size_t k) {
    if (progress) progress(0);
    assembleChunk(scene, source, keys[k], meshes[k]);
  });
  for (size_t k = 0; k < keys.size(); ++k) {
    if (meshes[k].triangles.empty())
      chunks_.erase(keys[k]);
    else
      chunks_[keys[k]] = std::make_shared<const ReceiverMesh>(std::move(meshes[k]));
  }
  counters.chunksMeshed += keys.size();
  for (const auto& entry : chunks_) counters.chunksKept += dirty.count(entry.first) ? 0 : 1;
}

void LatticeMeshMemo::assembleChunk(const Scene& scene, const MeshSource& source, const MeshChunkKey& key,
                                    ReceiverMesh& mesh) const {
  mesh.face = source.face;
  mesh.normal = source.frame.normal;
  ReceiverMeshBuilder builder(mesh, source.frame, eps_);
  const auto listed = chunkSquares_.find(key);
  if (listed == chunkSquares_.end()) return;
  std::vector<uint32_t> ids;
  const size_t lights = source.perLight.lightCount();
  for (uint32_t s : listed->second) {
    const Square& square = squares_[s];
    ids.resize(square.points.size());
    for (size_t i = 0; i < square.points.size(); ++i)
      ids[i] = builder.vertex(square.points[i],
                              sumLights(scene, std::span(square.lights).subspan(i * lights, lights)));
    for (const auto& t : square.triangles) mesh.triangles.push_back({ids[t[0]], ids[t[1]], ids[t[2]]});
  }
  mesh.positions.shrink_to_fit();
  mesh.irradiance.shrink_to_fit();
  mesh.classes.shrink_to_fit();
  mesh.triangles.shrink_to_fit();
}

size_t LatticeMeshMemo::cappedSquares() const {
  return size_t(std::count_if(squares_.begin(), squares_.end(), [](const Square& s) { return s.capped; }));
}

}  // namespace penumbra
