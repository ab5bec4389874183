#include "core/mesh/lattice_display_rule.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <unordered_set>

#include "core/illum/face_lookup.h"

namespace penumbra {

namespace {

// Whether some lattice square holds more than `above` live vertices of the tree.
bool denserThan(const DmTree& tree, double spacing, size_t above) {
  const HalfEdgeMesh& mesh = tree.mesh();
  std::unordered_map<uint64_t, uint32_t> counts;
  for (uint32_t v = 0; v < mesh.vertexSlots(); ++v) {
    const HalfEdgeMesh::Vertex vertex = mesh.vertex(VertexId(v));
    if (!vertex.alive) continue;
    const uint64_t x = uint64_t(int64_t(std::floor(vertex.position.x / spacing))) & 0xffffffffu;
    const uint64_t y = uint64_t(int64_t(std::floor(vertex.position.y / spacing))) & 0xffffffffu;
    if (++counts[x << 32 | y] > above) return true;
  }
  return false;
}

// The least signed distance of an occluder entry's geometry to the receiver's plane.
double lowestAbove(const Scene& scene, const PlaneFrame& frame, FaceId entry) {
  double lowest = std::numeric_limits<double>::infinity();
  const auto add = [&](const Face& face) {
    for (const Vec3& p : face.polygon) lowest = std::min(lowest, glm::dot(p - frame.origin, frame.normal));
  };
  if (isWholeObject(entry)) {
    if (scene.indexOfHandle(entry.object))
      for (const Face& face : scene.facesOfObject(entry.object)) add(face);
  } else if (const Face* face = findFace(scene, entry)) {
    add(*face);
  }
  return lowest;
}

// Whether an occluder in some live cell's list reaches the receiver's plane.
bool touchesPlane(const Scene& scene, const MeshSource& source) {
  const HalfEdgeMesh& mesh = source.tree.mesh();
  const double eps = scene.tolerance().length();
  std::unordered_set<const OccluderList*> seenLists;
  std::unordered_map<uint64_t, bool> touching;  // by entry face
  for (uint32_t c = 0; c < mesh.cellSlots(); ++c) {
    if (!mesh.cell(CellId(c)).alive) continue;
    const OccluderList& list = mesh.occluders(CellId(c));
    if (!seenLists.insert(&list).second) continue;
    for (const OccluderEntry& entry : list) {
      const uint64_t key = uint64_t(entry.face.object) << 32 | entry.face.face;
      auto [it, fresh] = touching.try_emplace(key, false);
      if (fresh) it->second = lowestAbove(scene, source.frame, entry.face) <= eps;
      if (it->second) return true;
    }
  }
  return false;
}

}  // namespace

bool displaysFromLattice(const Scene& scene, const MeshSource& source, const MeshGrid& grid) {
  if (grid.latticeAbove == 0 || !(grid.spacing > 0) || !(grid.latticeTolerance > 0)) return false;
  const Face* face = findFace(scene, source.face);
  if (!face || !face->cornerNormals.empty()) return false;
  const size_t lists = std::max<size_t>(1, source.tree.mesh().distinctOccluderLists());
  return source.tree.cellCount() > kCellsPerDistinctList * lists &&
         denserThan(source.tree, grid.spacing, grid.latticeAbove) && !touchesPlane(scene, source);
}

}  // namespace penumbra
