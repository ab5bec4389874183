#include "core/engine/resource_budget.h"

#include <vector>

#include "core/illum/vertex_illumination.h"

namespace penumbra {

TreeUsage usageOf(const DmTree& tree, size_t lights) {
  const HalfEdgeMesh& mesh = tree.mesh();
  // Per vertex slot: its position and out half-edge (HalfEdgeMesh keeps them in two arrays),
  // one value per light (Receiver::perLight) and the lit flag (Receiver::lit).
  const size_t perVertex = sizeof(Vec2) + sizeof(HalfEdgeId) + lights * sizeof(VertexLight) + sizeof(uint8_t);
  // A half-edge, and half of its pair's edge node.
  const size_t perHalfEdge = sizeof(HalfEdgeMesh::HalfEdge) + sizeof(NodeId) / 2;
  // A cell's share of the interned occluder lists: a few entries on average.
  const size_t perCell = sizeof(HalfEdgeMesh::Cell) + 2 * sizeof(OccluderEntry);
  TreeUsage usage;
  usage.nodes = tree.nodeCount();
  usage.vertices = tree.vertexCount();
  usage.bytes = tree.nodeSlots() * sizeof(DmNode) + tree.segmentSlots() * sizeof(NodeSegment) + mesh.halfEdgeSlots() * perHalfEdge +
                mesh.vertexSlots() * perVertex + mesh.cellSlots() * perCell;
  return usage;
}

ResourceBudget& ResourceBudget::operator=(const ResourceBudget& other) {
  limits_ = other.limits_;
  nodes_ = other.nodes_.load();
  vertices_ = other.vertices_.load();
  bytes_ = other.bytes_.load();
  return *this;
}

void ResourceBudget::checkFaces(size_t faces) const {
  if (faces > limits_.faces) throw ResourceLimitError("faces", faces, limits_.faces);
}

void ResourceBudget::change(const TreeUsage& before, const TreeUsage& after) {
  // Unsigned wrap-around cancels out: before was added earlier.
  const size_t nodes = nodes_ += after.nodes - before.nodes;
  const size_t vertices = vertices_ += after.vertices - before.vertices;
  const size_t bytes = bytes_ += after.bytes - before.bytes;
  if (nodes > limits_.treeNodes) throw ResourceLimitError("tree_nodes", nodes, limits_.treeNodes);
  if (vertices > limits_.vertices) throw ResourceLimitError("vertices", vertices, limits_.vertices);
  if (bytes > limits_.bytes) throw ResourceLimitError("bytes", bytes, limits_.bytes);
}

void ResourceBudget::clear() { nodes_ = vertices_ = bytes_ = 0; }

TreeUsage ResourceBudget::totals() const { return TreeUsage{nodes_.load(), vertices_.load(), bytes_.load()}; }

}  // namespace penumbra
