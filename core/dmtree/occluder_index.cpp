#include "core/dmtree/occluder_index.h"

namespace penumbra {

OccluderIndex::OccluderIndex(const DmTree& tree, const PlaneFrame& frame) : frame_(frame) {
  leafStart_.push_back(0);
  // A leaf: its cell's list, in the tree's order, into entries_; returns its child code.
  auto addLeaf = [&](NodeId n) {
    for (const OccluderEntry& e : tree.occluders(tree.node(n).cell()))
      if (e.face != kLightPlaneOccluder) entries_.push_back({e.light, e.face});
    leafStart_.push_back(uint32_t(entries_.size()));
    return -int32_t(leafStart_.size() - 1);  // leaf k is stored as -(k + 1)
  };
  if (tree.node(tree.root()).isLeaf()) {
    rootLeaf_ = -addLeaf(tree.root()) - 1;
    return;
  }
  // Depth first with an explicit stack: trees can be deep.
  struct Pending {
    NodeId node;
    int32_t parent;  // index in nodes_, -1 for the root
    bool front;
  };
  std::vector<Pending> stack{{tree.root(), -1, true}};
  while (!stack.empty()) {
    const Pending p = stack.back();
    stack.pop_back();
    const DmNode& d = tree.node(p.node);
    int32_t code;
    if (d.isLeaf()) {
      code = addLeaf(p.node);
    } else {
      code = int32_t(nodes_.size());
      nodes_.push_back({tree.segment(p.node).line, -1, -1});
      stack.push_back({d.back, code, false});
      stack.push_back({d.front, code, true});
    }
    if (p.parent >= 0)
      (p.front ? nodes_[size_t(p.parent)].front : nodes_[size_t(p.parent)].back) = code;
  }
}

int32_t OccluderIndex::leafOf(const Vec2& q) const {
  if (rootLeaf_ >= 0) return rootLeaf_;
  int32_t n = 0;
  // As DmTree::locate: a point on a line goes to the front.
  while (n >= 0) {
    const Node& node = nodes_[size_t(n)];
    n = node.line.distance(q) >= 0 ? node.front : node.back;
  }
  return -n - 1;
}

void OccluderIndex::occluders(const Vec3& p, uint32_t light, std::vector<FaceId>& out) const {
  const int32_t leaf = leafOf(frame_.to2D(p));
  for (uint32_t k = leafStart_[size_t(leaf)]; k < leafStart_[size_t(leaf) + 1]; ++k)
    if (entries_[k].light == light) out.push_back(entries_[k].face);
}

size_t OccluderIndex::bytes() const {
  return sizeof(*this) + nodes_.capacity() * sizeof(Node) +
         leafStart_.capacity() * sizeof(uint32_t) + entries_.capacity() * sizeof(Entry);
}

}  // namespace penumbra
