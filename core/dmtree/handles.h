// Typed index handles of the DM-tree and its half-edge mesh (pmp style): plain
// values that never dangle and copy for free. Thread-safe to copy and compare.
#pragma once

#include <cstdint>
#include <limits>

namespace penumbra {

template <class Tag>
struct IndexHandle {
  static constexpr uint32_t kInvalid = std::numeric_limits<uint32_t>::max();
  uint32_t index = kInvalid;
  constexpr IndexHandle() = default;
  explicit constexpr IndexHandle(uint32_t i) : index(i) {}
  bool is_valid() const { return index != kInvalid; }
  bool operator==(const IndexHandle&) const = default;
  auto operator<=>(const IndexHandle&) const = default;
};

struct NodeId : IndexHandle<NodeId> { using IndexHandle::IndexHandle; };
struct CellId : IndexHandle<CellId> { using IndexHandle::IndexHandle; };
struct VertexId : IndexHandle<VertexId> { using IndexHandle::IndexHandle; };
// Half-edges come in pairs: the twin of h is h.index ^ 1 (CGAL Surface_mesh habit).
struct HalfEdgeId : IndexHandle<HalfEdgeId> { using IndexHandle::IndexHandle; };

}  // namespace penumbra
