// DmTree::removeOccluder: deleting one occluder's entries and nodes (paper §3.1),
// first version: list entries plus bottom-up condensing of its leaf-pair nodes.
#include <algorithm>
#include <cmath>

#include "core/dmtree/dm_tree.h"

namespace penumbra {

// Whether some still-inserted occluder has a discontinuity along n's chord: the edge
// must stay although n's own occluder is gone.
bool DmTree::carriesLiveSegment(NodeId n) const {
  const double eps = tolerance_.length();
  const DmNode& d = node(n);
  const Vec2 dir{-d.line.normal.y, d.line.normal.x};
  double lo = INFINITY, hi = -INFINITY;
  for (const Vec2& p : mesh_.polygon(node(d.front).cell))
    if (std::abs(d.line.distance(p)) <= eps) {
      lo = std::min(lo, glm::dot(p, dir));
      hi = std::max(hi, glm::dot(p, dir));
    }
  for (const auto& [key, segments] : inserted_)
    for (const SingleTreeNode& s : segments) {
      if (std::abs(d.line.distance(s.a)) > eps || std::abs(d.line.distance(s.b)) > eps) continue;
      const double ta = glm::dot(s.a, dir), tb = glm::dot(s.b, dir);
      if (std::min(hi, std::max(ta, tb)) - std::max(lo, std::min(ta, tb)) > eps) return true;
    }
  return false;
}

void DmTree::condense(NodeId n, const OccluderKey& key, RemoveResult& result) {
  if (node(n).isLeaf()) return;
  condense(node(n).front, key, result);
  condense(node(n).back, key, result);
  const DmNode& d = node(n);
  const bool ours = d.orphan || (d.light == key.first && d.occluder == key.second);
  if (!ours || !node(d.front).isLeaf() || !node(d.back).isLeaf()) return;
  const CellId keep = node(d.front).cell, drop = node(d.back).cell;
  if (mesh_.cell(keep).occluders != mesh_.cell(drop).occluders) return;
  if (carriesLiveSegment(n)) return;
  const std::vector<VertexId> removed = mesh_.mergeCells(keep, drop, tolerance_.length());
  result.removedVertices.insert(result.removedVertices.end(), removed.begin(), removed.end());
  for (NodeId child : {d.front, d.back}) {
    nodes_[child.index].alive = false;
    nodes_[child.index].cell = CellId();
    --liveNodes_;
  }
  DmNode& m = nodes_[n.index];
  m.front = m.back = NodeId();
  m.cell = keep;
  m.orphan = m.partial = false;
  mesh_.cell(keep).leaf = n;
  ++result.nodesRemoved;
}

RemoveResult DmTree::removeOccluder(uint32_t light, FaceId occluder) {
  RemoveResult result;
  const OccluderKey key{light, occluder};
  const auto it = inserted_.find(key);
  if (it == inserted_.end()) return result;
  result.found = true;
  inserted_.erase(it);

  for (CellId c : cells()) {
    OccluderList& list = mesh_.cell(c).occluders;
    const auto end = std::remove_if(list.begin(), list.end(),
                                    [&](const OccluderEntry& e) { return e.light == light && e.face == occluder; });
    if (end == list.end()) continue;
    list.erase(end, list.end());
    result.changedCells.push_back(c);
  }
  condense(root_, key, result);
  // What could not be condensed stays as construction edges (TODO §3.1 in the header).
  for (DmNode& d : nodes_)
    if (d.alive && !d.isLeaf() && !d.orphan && d.light == light && d.occluder == occluder) {
      d.orphan = true;
      ++result.nodesKept;
    }
  return result;
}

}  // namespace penumbra
