// A frozen copy of one DM-tree's BSP and its cells' occluder lists (light-plane pseudo-occluders
// left out): what a renderer needs to find the faces that may hide a light from a point, without
// the engine. Built once from a tree (O(live nodes)); immutable, so queries are thread-safe.
#pragma once

#include <cstdint>
#include <vector>

#include "core/dmtree/dm_tree.h"
#include "core/geom/plane_frame.h"

namespace penumbra {

class OccluderIndex {
 public:
  // `frame`: the tree's 2D frame on its receiver (Engine::Receiver::frame).
  OccluderIndex(const DmTree& tree, const PlaneFrame& frame);

  // Appends to `out` the faces in the occluder list of light `light` of the cell containing p
  // (p on the receiver's plane; located as DmTree::locate does, so the same cell).
  void occluders(const Vec3& p, uint32_t light, std::vector<FaceId>& out) const;

  size_t nodeCount() const { return nodes_.size(); }
  size_t entryCount() const { return entries_.size(); }
  size_t bytes() const;

 private:
  struct Node {
    Line2 line;
    // Children: >= 0 a node index; < 0 the leaf -(child + 1) (an index into leafStart_).
    int32_t front = -1, back = -1;
  };
  struct Entry {
    uint32_t light;
    FaceId face;
  };
  int32_t leafOf(const Vec2& q) const;

  PlaneFrame frame_;
  std::vector<Node> nodes_;          // nodes_[0] is the root when the tree has a split
  int32_t rootLeaf_ = -1;            // a tree with no split: its single cell, else -1
  std::vector<uint32_t> leafStart_;  // leaves + 1 offsets into entries_
  std::vector<Entry> entries_;
};

}  // namespace penumbra
