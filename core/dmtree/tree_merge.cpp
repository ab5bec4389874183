// DmTree::insert: building the single tree and merging it into the total tree
// (Naylor et al. BSP merging with partial sub-hyperplanes, paper §2.3).
#include <algorithm>
#include <stdexcept>

#include "core/dmtree/dm_tree.h"

namespace penumbra {

namespace {

bool strictlyInside(const Polygon2& poly, const Vec2& p) {
  if (poly.size() < 3) return false;
  for (size_t i = 0; i < poly.size(); ++i)
    if (!(lineDistance(poly[i], poly[(i + 1) % poly.size()], p) > 0)) return false;
  return true;
}

}  // namespace

// Post-order for the nodes: children before parents (reversed, every node comes
// before its descendants).
void DmTree::collectCells(NodeId n, const Polygon2& region, std::vector<CellId>& out, const OccluderKey* key,
                          std::vector<NodeId>* nodes) const {
  const DmNode& d = node(n);
  if (d.isLeaf()) {
    out.push_back(d.cell());
    return;
  }
  // front = right of a→b for the two points a, b on the line.
  const Line2& line = segment(n).line;
  const Vec2 a = -line.offset * line.normal;
  const Vec2 b = a + Vec2{-line.normal.y, line.normal.x};
  const Split2 split = splitByLine(region, a, b, tolerance_.length());
  if (split.right.size() >= 3 && signedArea(split.right) > tolerance_.area())
    collectCells(d.front, split.right, out, key, nodes);
  if (split.left.size() >= 3 && signedArea(split.left) > tolerance_.area())
    collectCells(d.back, split.left, out, key, nodes);
  if (nodes && owner(n) == *key) nodes->push_back(n);
}

HalfEdgeMesh::CutResult DmTree::splitLeaf(NodeId n, const HalfEdgeMesh::CutPlan& plan, const SingleTreeNode& seg,
                                          const OccluderKey& owner, bool partial) {
  const HalfEdgeMesh::CutResult cut = mesh_.applyCut(plan, n);
  const NodeId front = addNode(n, cut.front);
  const NodeId back = addNode(n, cut.back);
  DmNode& d = nodes_[n.index];
  d.makeInternal(front, back);
  if (d.segment == DmNode::kNoSegment) d.segment = addSegment({});
  NodeSegment& s = segments_[d.segment];
  s.line = seg.line;
  s.owner = ownerIndex(owner);
  s.kind = seg.kind;
  s.partial = partial;
  s.orphan = false;
  s.copy = false;  // a reused slot may hold a former copy's flag
  return cut;
}

// Partitions cell c by the single-tree subtree s. A node splits the cell only where its
// segment crosses the cell's interior (the split then spans the cell: construction
// edges); a node whose line straddles the cell without its segment crossing it cannot
// classify the cell, so both of its subtrees are applied in turn.
void DmTree::partition(CellId c, const SingleTree& tree, int s, const Generator& gen,
                       std::vector<CellId>& pieces, InsertResult& result) {
  const SingleTreeNode& sn = tree.nodes[s];
  if (sn.region != SingleTreeNode::Region::None) {
    pieces.push_back(c);
    return;
  }
  const double eps = tolerance_.length();
  const HalfEdgeMesh::CutPlan plan = mesh_.planCut(c, sn.line, eps);
  if (plan.side > 0) return partition(c, tree, sn.front, gen, pieces, result);
  if (plan.side < 0) return partition(c, tree, sn.back, gen, pieces, result);

  const double length = glm::length(sn.b - sn.a);
  const Vec2 dir = (sn.b - sn.a) / length;
  const double t0 = glm::dot(plan.entry.point - sn.a, dir), t1 = glm::dot(plan.exit.point - sn.a, dir);
  const double chordLo = std::min(t0, t1), chordHi = std::max(t0, t1);
  const double lo = std::max(chordLo, 0.0), hi = std::min(chordHi, length);
  if (hi - lo <= eps) {
    std::vector<CellId> front;
    partition(c, tree, sn.front, gen, front, result);
    for (CellId f : front) partition(f, tree, sn.back, gen, pieces, result);
    return;
  }

  const HalfEdgeMesh::CutResult cut = splitLeaf(mesh_.cell(c).leaf, plan, sn, {gen.light, gen.occluder},
                                                lo > chordLo + eps || hi < chordHi - eps);
  result.newVertices.insert(result.newVertices.end(), cut.newVertices.begin(), cut.newVertices.end());
  ++result.nodesAdded;
  if (gen.beat && *gen.beat && result.nodesAdded % kCellsPerBeat == 0) (*gen.beat)();
  partition(cut.front, tree, sn.front, gen, pieces, result);
  partition(cut.back, tree, sn.back, gen, pieces, result);
}

bool DmTree::inUmbraOf(CellId c, uint32_t light) const {
  for (const OccluderEntry& e : mesh_.occluders(c)) {
    if (!e.umbra) return false;  // umbra entries come first
    if (e.light != light) continue;
    const auto it = inserted_.find({light, e.face});
    if (it != inserted_.end() && it->second.culls()) return true;
  }
  return false;
}

InsertResult DmTree::insert(const SingleShadow& shadow, const std::function<void()>& beat) {
  // Check first, then change.
  const OccluderKey key{shadow.light, shadow.occluder};
  if (inserted_.count(key)) throw std::invalid_argument("DM-tree: occluder already inserted for this light");
  for (const CriticalSegment& s : shadow.segments)
    if (!std::isfinite(s.a.x) || !std::isfinite(s.a.y) || !std::isfinite(s.b.x) || !std::isfinite(s.b.y))
      throw std::invalid_argument("DM-tree: non-finite segment end point");
  for (const Polygon2* poly : {&shadow.penumbra, &shadow.umbra})
    for (const Vec2& p : *poly)
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw std::invalid_argument("DM-tree: non-finite region");

  InsertResult result;
  const SingleTree tree = buildSingleTree(shadow, tolerance_, beat);
  if (tree.root < 0) return result;

  // The total-tree leaves the penumbra overlaps with positive area.
  std::vector<CellId> targets;
  collectCells(root_, tree.penumbra, targets);
  record(key, shadow);

  const Generator gen{shadow.light, shadow.occluder, &beat};
  for (size_t t = 0; t < targets.size(); ++t) {
    const CellId target = targets[t];
    if (beat && t % kCellsPerBeat == kCellsPerBeat - 1) beat();
    if (umbraCulling_ && inUmbraOf(target, shadow.light)) {
      inserted_[key].culled = true;
      continue;
    }
    std::vector<CellId> pieces;
    partition(target, tree, tree.root, gen, pieces, result);
    // No region boundary crosses a piece: one interior point classifies it.
    for (CellId piece : pieces) {
      const Vec2 p = areaCentroid(mesh_.polygon(piece));
      if (!strictlyInside(tree.penumbra, p)) continue;
      const bool umbra = strictlyInside(tree.umbra, p);
      OccluderList& list = scratchList_;
      list = mesh_.occluders(piece);
      const OccluderEntry entry{shadow.light, shadow.occluder, umbra};
      if (umbra)
        list.insert(std::find_if(list.begin(), list.end(), [](const OccluderEntry& e) { return !e.umbra; }), entry);
      else
        list.push_back(entry);
      mesh_.setOccluders(piece, list);
      result.changedCells.push_back(piece);
    }
  }
  return result;
}

}  // namespace penumbra
