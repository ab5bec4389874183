#include "core/dmtree/dm_tree.h"

#include "core/geom/resource_limit.h"

#include <algorithm>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <string>

namespace penumbra {

DmTree::DmTree(const Polygon2& receiver, const Tolerance& tolerance) : tolerance_(tolerance) {
  const CellId c = mesh_.reset(receiver, tolerance_.length());
  receiver_ = mesh_.polygon(c);
  receiverArea_ = signedArea(receiver_);
  root_ = addNode(NodeId(), c);
}

void DmTree::record(const OccluderKey& key, const SingleShadow& shadow) {
  Inserted& entry = inserted_[key];
  entry.shadow = shadow;
  entry.sequence = nextSequence_++;
}

NodeId DmTree::addNode(NodeId parent, CellId cell) {
  if (nodes_.size() >= nodeLimit_) throw ResourceLimitError("tree_nodes", nodes_.size() + 1, nodeLimit_);
  DmNode n;
  n.parent = parent;
  if (cell.is_valid()) n.makeLeaf(cell);
  nodes_.push_back(n);
  ++liveNodes_;
  const NodeId id(static_cast<uint32_t>(nodes_.size() - 1));
  if (cell.is_valid()) mesh_.setLeaf(cell, id);
  return id;
}

uint32_t DmTree::ownerIndex(const OccluderKey& key) {
  const auto [it, added] = ownerIndex_.try_emplace(key, uint32_t(owners_.size()));
  if (added) owners_.push_back(key);
  return it->second;
}

void DmTree::compactOwners() {
  // Keys of removed occluders stay until no live node carries them; past twice the live
  // keys the table is rebuilt from the live internal nodes (an editing session adds new
  // objects' faces for ever, so the table would otherwise only grow).
  if (owners_.size() <= 2 * inserted_.size() + 64) return;
  constexpr uint32_t kUnseen = UINT32_MAX;
  std::vector<uint32_t> remap(owners_.size(), kUnseen);
  std::vector<OccluderKey> kept;
  std::vector<bool> used(segments_.size(), false);
  for (const DmNode& d : nodes_) {
    if (!d.alive || d.isLeaf() || d.segment == DmNode::kNoSegment) continue;
    NodeSegment& s = segments_[d.segment];
    if (remap[s.owner] == kUnseen) {
      remap[s.owner] = uint32_t(kept.size());
      kept.push_back(owners_[s.owner]);
    }
    s.owner = remap[s.owner];
    used[d.segment] = true;
  }
  for (size_t i = 0; i < segments_.size(); ++i)
    if (!used[i]) segments_[i].owner = 0;  // a spare slot: splitLeaf sets its owner before use
  owners_ = std::move(kept);
  ownerIndex_.clear();
  for (uint32_t i = 0; i < owners_.size(); ++i) ownerIndex_.emplace(owners_[i], i);
}

uint32_t DmTree::addSegment(const NodeSegment& s) {
  if (segments_.size() >= DmNode::kNoSegment)
    throw ResourceLimitError("tree_nodes", segments_.size() + 1, DmNode::kNoSegment);
  segments_.push_back(s);
  return uint32_t(segments_.size() - 1);
}

std::vector<CellId> DmTree::cells() const {
  std::vector<CellId> out;
  for (uint32_t i = 0; i < mesh_.cellSlots(); ++i)
    if (mesh_.cell(CellId(i)).alive) out.push_back(CellId(i));
  return out;
}

std::vector<VertexId> DmTree::vertices() const {
  std::vector<VertexId> out;
  for (uint32_t i = 0; i < mesh_.vertexSlots(); ++i)
    if (mesh_.vertex(VertexId(i)).alive) out.push_back(VertexId(i));
  return out;
}

CellId DmTree::locate(const Vec2& p) const {
  NodeId n = root_;
  while (!node(n).isLeaf()) n = segment(n).line.distance(p) >= 0 ? node(n).front : node(n).back;
  return node(n).cell();
}

void DmTree::validate() const {
  auto fail = [](const std::string& what) { throw std::logic_error("DM-tree: " + what); };
  const double eps = tolerance_.length();
  mesh_.validate(eps, receiverArea_);

  // BSP: reachable nodes are exactly the live ones; leaves ↔ cells one-to-one.
  size_t reached = 0, leaves = 0;
  std::vector<NodeId> stack{root_};
  if (node(root_).parent.is_valid()) fail("root has a parent");
  while (!stack.empty()) {
    const NodeId n = stack.back();
    stack.pop_back();
    const DmNode& d = node(n);
    if (!d.alive) fail("dead node reachable");
    ++reached;
    if (d.isLeaf()) {
      ++leaves;
      if (!mesh_.cell(d.cell()).alive || mesh_.cell(d.cell()).leaf != n) fail("leaf and cell disagree");
      continue;
    }
    if (d.segment == DmNode::kNoSegment || segment(n).owner >= owners_.size()) fail("internal node without a segment or owner");
    for (NodeId c : {d.front, d.back}) {
      if (!c.is_valid() || node(c).parent != n) fail("child/parent mismatch");
      stack.push_back(c);
    }
  }
  if (reached != liveNodes_) fail("live nodes not in the tree");
  if (ownerIndex_.size() != owners_.size()) fail("owner table and its index differ");
  if (leaves != mesh_.cellCount()) fail("leaf count differs from cell count");

  for (CellId c : cells()) {
    const Polygon2 poly = mesh_.polygon(c);
    Vec2 centroid{0.0};
    for (const Vec2& p : poly) centroid += p;
    centroid /= double(poly.size());
    // Each cell lies on its side of every ancestor's line.
    NodeId child = mesh_.cell(c).leaf;
    for (NodeId n = node(child).parent; n.is_valid(); child = n, n = node(n).parent) {
      const double side = node(n).front == child ? 1.0 : -1.0;
      double reach = 0;  // how far the cell reaches onto its side
      for (const Vec2& p : poly) {
        const double d = side * segment(n).line.distance(p);
        if (d < -eps) fail("cell vertex on the wrong side of an ancestor");
        reach = std::max(reach, d);
      }
      // A cell reaching no farther than 2 eps onto its side has no side to check its centroid
      // against: vertices within eps of a line count as on it, so between this line and one
      // within eps of it (crossing it at a shallow angle) lies a sliver that straddles both
      // (fuzz finding crashes/edit_frame/near-coplanar-light-edge.json: 9e-9 m wide, eps 9e-9).
      if (reach > 2 * eps && !(side * segment(n).line.distance(centroid) > 0))
        fail("cell centroid on the wrong side of an ancestor");
    }
    // Occluder lists: umbra entries first, one entry per (light, face).
    const OccluderList& list = mesh_.occluders(c);
    std::set<OccluderKey> seen;
    bool partialSeen = false;
    for (const OccluderEntry& e : list) {
      if (!seen.insert({e.light, e.face}).second) fail("duplicate occluder entry");
      if (e.umbra && partialSeen) fail("umbra entry after a partial one");
      partialSeen |= !e.umbra;
    }
  }
  // Every mesh edge is the receiver's boundary or made by a live internal node.
  for (uint32_t i = 0; i < mesh_.halfEdgeSlots(); ++i) {
    const HalfEdgeMesh::HalfEdge& h = mesh_.halfEdge(HalfEdgeId(i));
    const NodeId made = mesh_.node(HalfEdgeId(i));
    if (!h.alive() || !made.is_valid()) continue;
    if (!node(made).alive || node(made).isLeaf()) fail("edge made by a dead or leaf node");
    const Line2& line = segment(made).line;
    for (VertexId v : {h.origin, mesh_.destination(HalfEdgeId(i))})
      if (std::abs(line.distance(mesh_.vertex(v).position)) > eps) fail("edge off its node's line");
  }
}

}  // namespace penumbra
