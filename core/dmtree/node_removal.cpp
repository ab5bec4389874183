// DmTree::removeOccluder: deleting one occluder's list entries and tree nodes (paper
// §3.1): unlink a node's edge, extend the basis subtree across the freed cell,
// re-insert the other subtree's live segments, condense what no longer separates.
#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "core/dmtree/dm_tree.h"

namespace penumbra {

namespace {

// Clips p→q to the convex CCW polygon grown by eps; false if less than eps is left.
bool clipSegment(const Polygon2& poly, Vec2& p, Vec2& q, double eps) {
  double t0 = 0, t1 = 1;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec2 a = poly[i], b = poly[(i + 1) % poly.size()];
    const double dp = lineDistance(a, b, p) + eps, dq = lineDistance(a, b, q) + eps;
    if (dp < 0 && dq < 0) return false;
    if (dp < 0) t0 = std::max(t0, dp / (dp - dq));
    else if (dq < 0) t1 = std::min(t1, dp / (dp - dq));
  }
  if (!(t1 > t0)) return false;
  const Vec2 a = p + t0 * (q - p), b = p + t1 * (q - p);
  p = a;
  q = b;
  return glm::length(q - p) > eps;
}

Vec2 along(const Line2& line) { return {-line.normal.y, line.normal.x}; }

// Where `line` crosses a convex region, as an interval of positions along the line.
bool chordExtent(const Line2& line, const Polygon2& region, double eps, double& lo, double& hi) {
  const Vec2 dir = along(line);
  lo = INFINITY;
  hi = -INFINITY;
  const size_t m = region.size();
  for (size_t i = 0; i < m; ++i) {
    const Vec2 p = region[i], q = region[(i + 1) % m];
    const double dp = line.distance(p), dq = line.distance(q);
    if (std::abs(dp) <= eps) {
      lo = std::min(lo, glm::dot(p, dir));
      hi = std::max(hi, glm::dot(p, dir));
    } else if ((dp > eps && dq < -eps) || (dp < -eps && dq > eps)) {
      const Vec2 x = p + (dp / (dp - dq)) * (q - p);
      lo = std::min(lo, glm::dot(x, dir));
      hi = std::max(hi, glm::dot(x, dir));
    }
  }
  return hi - lo > eps;
}

}  // namespace

void DmTree::killNode(NodeId n) {
  DmNode& d = nodes_[n.index];
  d.alive = false;
  d.cell = CellId();
  d.front = d.back = NodeId();
  --liveNodes_;
}

// The leaves below n whose cells touch the segment p→q with positive length.
void DmTree::leavesAlong(NodeId n, const Vec2& p, const Vec2& q, std::vector<NodeId>& out) const {
  const double eps = tolerance_.length();
  if (!(glm::length(q - p) > eps)) return;
  const DmNode& d = node(n);
  if (d.isLeaf()) {
    out.push_back(n);
    return;
  }
  const double dp = d.line.distance(p), dq = d.line.distance(q);
  if (std::abs(dp) <= eps && std::abs(dq) <= eps) {  // along n's edge: both sides touch it
    leavesAlong(d.front, p, q, out);
    leavesAlong(d.back, p, q, out);
  } else if (dp >= -eps && dq >= -eps) {
    leavesAlong(d.front, p, q, out);
  } else if (dp <= eps && dq <= eps) {
    leavesAlong(d.back, p, q, out);
  } else {
    const Vec2 x = p + (dp / (dp - dq)) * (q - p);
    leavesAlong(dp > 0 ? d.front : d.back, p, x, out);
    leavesAlong(dq > 0 ? d.front : d.back, x, q, out);
  }
}

Polygon2 DmTree::regionOf(NodeId n) const {
  Polygon2 region = receiver_;
  for (NodeId child = n, p = node(n).parent; p.is_valid() && !region.empty(); child = p, p = node(p).parent) {
    const DmNode& d = node(p);
    const Vec2 a = -d.line.offset * d.line.normal;
    const Split2 split = splitByLine(region, a, a + along(d.line), tolerance_.length());
    region = d.front == child ? split.right : split.left;  // front = right of a→b
  }
  return region;
}

bool DmTree::chordOf(NodeId n, double& lo, double& hi) const {
  // The cells below n tile its region, so the chord is the union of their chords;
  // walking a few cells beats splitting the receiver by every ancestor's line.
  constexpr size_t kMaxCells = 64;
  const double eps = tolerance_.length();
  const Line2& line = node(n).line;
  std::vector<NodeId> leaves, stack{n};
  while (!stack.empty() && leaves.size() <= kMaxCells) {
    const NodeId k = stack.back();
    stack.pop_back();
    if (node(k).isLeaf()) leaves.push_back(k);
    else {
      stack.push_back(node(k).back);
      stack.push_back(node(k).front);
    }
  }
  if (!stack.empty()) return chordExtent(line, regionOf(n), eps, lo, hi);
  lo = INFINITY;
  hi = -INFINITY;
  for (NodeId leaf : leaves) {
    double a, b;
    if (!chordExtent(line, mesh_.polygon(node(leaf).cell), eps, a, b)) continue;
    lo = std::min(lo, a);
    hi = std::max(hi, b);
  }
  return hi - lo > eps;
}

// A still-inserted occluder's discontinuity overlapping n's chord [lo, hi] (positions
// along n's line): the edge must stay although n's own generator is gone.
const SingleTreeNode* DmTree::liveSegmentOn(NodeId n, double lo, double hi, const std::vector<OccluderKey>& keys,
                                            OccluderKey* owner) const {
  const double eps = tolerance_.length();
  const Line2& line = node(n).line;
  const Vec2 dir = along(line);
  for (const OccluderKey& key : keys) {
    const auto it = inserted_.find(key);
    if (it == inserted_.end()) continue;
    for (const SingleTreeNode& s : it->second.segments) {
      if (std::abs(line.distance(s.a)) > eps || std::abs(line.distance(s.b)) > eps) continue;
      const double ta = glm::dot(s.a, dir), tb = glm::dot(s.b, dir);
      if (std::min(hi, std::max(ta, tb)) - std::max(lo, std::min(ta, tb)) > eps) {
        if (owner) *owner = key;
        return &s;
      }
    }
  }
  return nullptr;
}

// Post-order: children before parents (reversed, every node comes before its
// descendants).
void DmTree::collectOccluderNodes(NodeId n, const Polygon2& region, const OccluderKey& key,
                                  std::vector<NodeId>& out) const {
  const DmNode& d = node(n);
  if (d.isLeaf()) return;
  const Vec2 a = -d.line.offset * d.line.normal;
  const Split2 split = splitByLine(region, a, a + along(d.line), tolerance_.length());
  if (split.right.size() >= 3 && signedArea(split.right) > tolerance_.area())
    collectOccluderNodes(d.front, split.right, key, out);
  if (split.left.size() >= 3 && signedArea(split.left) > tolerance_.area())
    collectOccluderNodes(d.back, split.left, key, out);
  if (d.light == key.first && d.occluder == key.second) out.push_back(n);
}

// Merges every cell below n into one; n becomes its leaf.
void DmTree::collapse(NodeId n, RemoveResult& result) {
  if (node(n).isLeaf()) return;
  const NodeId front = node(n).front, back = node(n).back;
  collapse(front, result);
  collapse(back, result);
  const CellId keep = node(front).cell, drop = node(back).cell;
  const std::vector<VertexId> removed = mesh_.mergeCells(keep, drop, tolerance_.length());
  result.removedVertices.insert(result.removedVertices.end(), removed.begin(), removed.end());
  killNode(front);
  killNode(back);
  DmNode& d = nodes_[n.index];
  d.cell = keep;
  mesh_.setLeaf(keep, n);
  if (d.light == removing_.first && d.occluder == removing_.second) ++result.nodesRemoved;
  else ++result.nodesCollapsed;
}

// Step 2: the piece of the freed cell under basis node n is cut by n's line (the
// dangling edge extended) until it reaches a leaf, then joins that leaf's cell across
// the deleted edge. Only lines that crossed the deleted edge can cut a piece.
void DmTree::extendInto(NodeId n, CellId piece, std::vector<NodeId>& extended, RemoveResult& result) {
  const double eps = tolerance_.length();
  if (node(n).isLeaf()) {
    const CellId keep = node(n).cell;
    const std::vector<VertexId> removed = mesh_.mergeCells(keep, piece, eps);
    result.removedVertices.insert(result.removedVertices.end(), removed.begin(), removed.end());
    result.changedCells.push_back(keep);
    return;
  }
  const HalfEdgeMesh::CutPlan plan = mesh_.planCut(piece, node(n).line, eps);
  if (plan.side > 0) return extendInto(node(n).front, piece, extended, result);
  if (plan.side < 0) return extendInto(node(n).back, piece, extended, result);
  const HalfEdgeMesh::CutResult cut = mesh_.applyCut(plan, n);
  result.newVertices.insert(result.newVertices.end(), cut.newVertices.begin(), cut.newVertices.end());
  nodes_[n.index].partial = true;
  extended.push_back(n);
  const NodeId front = node(n).front, back = node(n).back;
  extendInto(front, cut.front, extended, result);
  extendInto(back, cut.back, extended, result);
}

// Step 3: filters the live segment piece p→q down from n; where it crosses a leaf
// cell's interior the cell is split along it (the split spans the cell).
void DmTree::filterSegment(NodeId n, const Vec2& p, const Vec2& q, const SingleTreeNode& seg, const OccluderKey& key,
                           RemoveResult& result) {
  const double eps = tolerance_.length();
  if (!node(n).isLeaf()) {
    const Line2 line = node(n).line;
    const NodeId front = node(n).front, back = node(n).back;
    const double dp = line.distance(p), dq = line.distance(q);
    if (std::abs(dp) <= eps && std::abs(dq) <= eps) return;  // on n's edge already
    if (dp >= -eps && dq >= -eps) return filterSegment(front, p, q, seg, key, result);
    if (dp <= eps && dq <= eps) return filterSegment(back, p, q, seg, key, result);
    const Vec2 x = p + (dp / (dp - dq)) * (q - p);
    filterSegment(dp > 0 ? front : back, p, x, seg, key, result);
    filterSegment(dq > 0 ? front : back, x, q, seg, key, result);
    return;
  }
  const CellId c = node(n).cell;
  const HalfEdgeMesh::CutPlan plan = mesh_.planCut(c, seg.line, eps);
  if (plan.side != 0) return;
  const double length = glm::length(seg.b - seg.a);
  const Vec2 dir = (seg.b - seg.a) / length;
  const double t0 = glm::dot(plan.entry.point - seg.a, dir), t1 = glm::dot(plan.exit.point - seg.a, dir);
  const double tp = glm::dot(p - seg.a, dir), tq = glm::dot(q - seg.a, dir);
  const double chordLo = std::min(t0, t1), chordHi = std::max(t0, t1);
  const double lo = std::max(chordLo, std::min(tp, tq)), hi = std::min(chordHi, std::max(tp, tq));
  if (hi - lo <= eps) return;
  const HalfEdgeMesh::CutResult cut =
      splitLeaf(n, plan, seg, key, lo, hi, lo > chordLo + eps || hi < chordHi - eps);
  result.newVertices.insert(result.newVertices.end(), cut.newVertices.begin(), cut.newVertices.end());
  result.changedCells.push_back(cut.front);
  result.changedCells.push_back(cut.back);
  ++result.nodesReinserted;
}

// Removes n's split if its two cells are leaves with equal lists and its edge carries
// no live discontinuity (paper: "the subtrees created are condensed", edge 14b).
void DmTree::condenseLeafPair(NodeId n, const std::vector<OccluderKey>& keys, RemoveResult& result) {
  const DmNode& d = node(n);
  if (!d.alive || d.isLeaf() || !node(d.front).isLeaf() || !node(d.back).isLeaf()) return;
  const CellId keep = node(d.front).cell, drop = node(d.back).cell;
  if (mesh_.cell(keep).occluders != mesh_.cell(drop).occluders) return;
  double lo, hi;
  if (chordOf(n, lo, hi) && liveSegmentOn(n, lo, hi, keys, nullptr)) return;
  const std::vector<VertexId> removed = mesh_.mergeCells(keep, drop, tolerance_.length());
  result.removedVertices.insert(result.removedVertices.end(), removed.begin(), removed.end());
  result.changedCells.push_back(keep);
  const NodeId front = d.front, back = d.back;
  killNode(front);
  killNode(back);
  DmNode& m = nodes_[n.index];
  m.cell = keep;
  m.partial = m.orphan = false;
  mesh_.setLeaf(keep, n);
  if (m.light == removing_.first && m.occluder == removing_.second) ++result.nodesRemoved;
  else ++result.nodesCondensed;
}

void DmTree::deleteNode(NodeId e, const OccluderKey& key, RemoveResult& result) {
  const double eps = tolerance_.length();
  const NodeId front = node(e).front, back = node(e).back;
  const Line2 deletedLine = node(e).line;
  double lo, hi;
  if (!chordOf(e, lo, hi)) throw std::logic_error("DM-tree: a node without an edge");
  const Vec2 origin = -deletedLine.offset * deletedLine.normal, dir = along(deletedLine);
  const Vec2 chordP = origin + lo * dir, chordQ = origin + hi * dir;
  // The cells along e's edge, on each side.
  std::vector<NodeId> along[2];
  leavesAlong(front, chordP, chordQ, along[0]);
  leavesAlong(back, chordP, chordQ, along[1]);

  // Occluders that can have a discontinuity on e's edge: those covering a cell along it
  // (a segment always borders a cell its occluder covers).
  std::set<OccluderKey> keySet;
  auto addListed = [&](NodeId leaf) {
    for (const OccluderEntry& entry : mesh_.cell(node(leaf).cell).occluders) keySet.insert({entry.light, entry.face});
  };
  for (const auto& side : along)
    for (NodeId leaf : side) addListed(leaf);
  auto sortedKeys = [&] {
    keySet.erase(key);
    std::vector<OccluderKey> keys;
    for (const OccluderKey& k : keySet)
      if (inserted_.count(k)) keys.push_back(k);
    std::sort(keys.begin(), keys.end(), [&](const OccluderKey& x, const OccluderKey& y) {
      return inserted_.at(x).sequence < inserted_.at(y).sequence;
    });
    return keys;
  };

  // A live segment on e's edge: e stays, now generated by that occluder.
  OccluderKey owner;
  if (const SingleTreeNode* s = liveSegmentOn(e, lo, hi, sortedKeys(), &owner)) {
    DmNode& d = nodes_[e.index];
    d.light = owner.first;
    d.occluder = owner.second;
    d.kind = s->kind;
    d.lightElement = s->lightElement;
    d.occluderElement = s->occluderElement;
    d.a = s->a;
    d.b = s->b;
    d.partial = true;
    ++result.nodesRelabeled;
    return;
  }
  if (node(front).isLeaf() && node(back).isLeaf() &&
      mesh_.cell(node(front).cell).occluders != mesh_.cell(node(back).cell).occluders) {
    // Different lists but no live segment between them: a numerical disagreement;
    // keep the edge rather than give one side the wrong list.
    nodes_[e.index].orphan = true;
    ++result.nodesKept;
    return;
  }

  // Step 1 (counting): dangling edges are the other edges ending on e's edge.
  size_t dangling[2] = {0, 0};
  for (int side = 0; side < 2; ++side)
    for (NodeId leaf : along[side])
      for (HalfEdgeId h : mesh_.loop(node(leaf).cell)) {
        if (mesh_.halfEdge(h).node != e) continue;
        const VertexId v = mesh_.halfEdge(h).origin;
        const Vec2 x = mesh_.vertex(v).position;
        const double t = glm::dot(x, dir);
        const NodeId other = mesh_.halfEdge(mesh_.halfEdge(h).prev).node;
        if (other != e && t > lo + eps && t < hi - eps) ++dangling[side];  // not at the edge's ends
      }
  // Live internal nodes per side (the removed occluder's own vanish with a collapse),
  // counted on both sides in turn and only until the choice is certain: the side to
  // re-insert is usually small, the other may be most of the tree.
  struct Count {
    std::vector<NodeId> stack;
    size_t size = 0;
    bool done() const { return stack.empty(); }
  };
  Count count[2] = {{{front}}, {{back}}};
  auto step = [&](Count& c) {
    const DmNode& d = node(c.stack.back());
    c.stack.pop_back();
    if (d.isLeaf()) return;
    if (!(d.light == key.first && d.occluder == key.second)) ++c.size;
    c.stack.push_back(d.front);
    c.stack.push_back(d.back);
  };
  // cost(side as basis) = (D_side + 1)·size_other; an unfinished count bounds its side's size
  // from below. A finished side is surely the one to re-insert once keeping it as basis
  // would cost more: (D_mine + 1)·size_other > (D_other + 1)·size_mine.
  auto certain = [&] {
    for (int side = 0; side < 2; ++side) {
      const Count &mine = count[side], &other = count[1 - side];
      if (mine.done() && (dangling[side] + 1) * other.size > (dangling[1 - side] + 1) * mine.size) return true;
    }
    return count[0].done() && count[1].done();
  };
  while (!certain()) {
    if (!count[0].done()) step(count[0]);
    if (!count[1].done()) step(count[1]);
  }
  // Step 2: the basis a minimises E[cost_a] = (D_a + 1)·size_b (the paper's D_a·size_b;
  // the +1 counts re-inserting b even when a has nothing to extend). With one side
  // unfinished, its true size only makes the other side the cheaper basis.
  const size_t size[2] = {count[0].size, count[1].size};
  const bool frontBasis = count[0].done() && count[1].done()
                              ? (dangling[0] + 1) * size[1] <= (dangling[1] + 1) * size[0]
                              : !count[0].done();
  const NodeId a = frontBasis ? front : back, b = frontBasis ? back : front;
  const double basisSide = frontBasis ? 1.0 : -1.0;

  // b's cells (one point of each new cell is classified against them, by descending
  // a copy of b's lines: paper step 3, "classifying one point will suffice") and
  // generators.
  struct SavedNode {
    Line2 line;
    int front = -1, back = -1;
    int list = -1;  // leaves: index into oldLists
  };
  std::vector<SavedNode> saved;
  std::vector<OccluderList> oldLists;
  {
    std::vector<std::pair<NodeId, int>> stack{{b, -1}};  // node, saved parent slot (front first)
    while (!stack.empty()) {
      const auto [k, parentSlot] = stack.back();
      stack.pop_back();
      const int slot = int(saved.size());
      saved.emplace_back();
      if (parentSlot >= 0) {
        SavedNode& parent = saved[size_t(parentSlot)];
        if (parent.front < 0) parent.front = slot;
        else parent.back = slot;
      }
      const DmNode& d = node(k);
      if (d.isLeaf()) {
        saved[size_t(slot)].list = int(oldLists.size());
        oldLists.push_back(mesh_.cell(d.cell).occluders);
        addListed(k);
        continue;
      }
      saved[size_t(slot)].line = d.line;
      stack.push_back({d.back, slot});   // popped second: the back child
      stack.push_back({d.front, slot});  // popped first: the front child
    }
  }
  {
    std::vector<NodeId> stack{b};
    while (!stack.empty()) {
      const DmNode& d = node(stack.back());
      stack.pop_back();
      if (d.isLeaf()) continue;
      keySet.insert({d.light, d.occluder});
      stack.push_back(d.front);
      stack.push_back(d.back);
    }
  }
  const std::vector<OccluderKey> keys = sortedKeys();

  collapse(b, result);
  const CellId freed = node(b).cell;
  const Polygon2 freedPolygon = mesh_.polygon(freed);
  const size_t firstChanged = result.changedCells.size();
  std::vector<NodeId> extended;
  extendInto(a, freed, extended, result);
  killNode(b);

  // Unlink e: a takes its place.
  const NodeId parent = node(e).parent;
  nodes_[a.index].parent = parent;
  if (!parent.is_valid()) root_ = a;
  else if (node(parent).front == e) nodes_[parent.index].front = a;
  else nodes_[parent.index].back = a;
  killNode(e);
  ++result.nodesRemoved;
  for (NodeId leaf : along[frontBasis ? 0 : 1])
    for (HalfEdgeId h : mesh_.loop(node(leaf).cell))
      if (mesh_.halfEdge(h).node == e) throw std::logic_error("DM-tree: an edge of a deleted node is left");

  // Step 3: b's live discontinuities (and any on e's line) go back in, in insertion order.
  // A bounding-box test first: most of an occluder's segments lie far from the cell.
  Vec2 boxMin = freedPolygon[0], boxMax = freedPolygon[0];
  for (const Vec2& v : freedPolygon) {
    boxMin = glm::min(boxMin, v);
    boxMax = glm::max(boxMax, v);
  }
  boxMin -= Vec2(2 * eps);
  boxMax += Vec2(2 * eps);
  for (const OccluderKey& k : keys)
    for (const SingleTreeNode& seg : inserted_.at(k).segments) {
      const Vec2 segMin = glm::min(seg.a, seg.b), segMax = glm::max(seg.a, seg.b);
      if (glm::any(glm::lessThan(segMax, boxMin)) || glm::any(glm::greaterThan(segMin, boxMax))) continue;
      Vec2 p = seg.a, q = seg.b;
      if (clipSegment(freedPolygon, p, q, eps)) filterSegment(a, p, q, seg, k, result);
    }
  // Cells reaching into b's former half take the list of the old cell around their centroid.
  std::vector<CellId> touched(result.changedCells.begin() + firstChanged, result.changedCells.end());
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  for (CellId c : touched) {
    if (!mesh_.cell(c).alive) continue;
    const Vec2 p = areaCentroid(mesh_.polygon(c));
    if (!(basisSide * deletedLine.distance(p) < 0) || saved.empty()) continue;
    size_t k = 0;
    while (saved[k].list < 0) k = size_t(saved[k].line.distance(p) >= 0 ? saved[k].front : saved[k].back);
    const OccluderList& old = oldLists[size_t(saved[k].list)];
    if (mesh_.cell(c).occluders != old) mesh_.occludersForWrite(c) = old;
  }
  // Extended splits, deepest first (they were found top-down).
  for (auto it = extended.rbegin(); it != extended.rend(); ++it) condenseLeafPair(*it, keys, result);
}

void DmTree::rebuild() {
  std::vector<std::pair<uint64_t, SingleShadow>> ordered;
  for (const auto& [key, entry] : inserted_) ordered.push_back({entry.sequence, entry.shadow});
  std::sort(ordered.begin(), ordered.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  inserted_.clear();
  nodes_.clear();
  liveNodes_ = 0;
  const CellId c = mesh_.reset(receiver_, tolerance_.length());
  root_ = addNode(NodeId(), c);
  for (const auto& [sequence, shadow] : ordered) insert(shadow);
}

RemoveResult DmTree::removeOccluder(uint32_t light, FaceId occluder) {
  RemoveResult result;
  const OccluderKey key{light, occluder};
  const auto it = inserted_.find(key);
  if (it == inserted_.end()) return result;
  result.found = true;
  const Polygon2 penumbra = it->second.penumbra;
  result.penumbra = penumbra;
  inserted_.erase(it);
  const size_t firstVertex = mesh_.vertexSlots();
  removing_ = key;
  try {
    // Its list entries: only cells under its penumbra can hold one.
    std::vector<CellId> covered;
    if (!penumbra.empty()) collectCells(root_, penumbra, covered);
    for (CellId c : covered) {
      const auto listed = [&](const OccluderEntry& e) { return e.light == light && e.face == occluder; };
      const OccluderList& held = mesh_.cell(c).occluders;
      if (std::none_of(held.begin(), held.end(), listed)) continue;
      OccluderList& list = mesh_.occludersForWrite(c);
      list.erase(std::remove_if(list.begin(), list.end(), listed), list.end());
      result.changedCells.push_back(c);
    }
    // Its nodes, top-down: those in a subtree collapsed for re-insertion go with it.
    std::vector<NodeId> doomed;
    if (!penumbra.empty()) collectOccluderNodes(root_, penumbra, key, doomed);
    std::reverse(doomed.begin(), doomed.end());
    for (NodeId e : doomed) {
      const DmNode& d = node(e);
      if (!d.alive || d.isLeaf() || d.light != light || d.occluder != occluder) continue;
      deleteNode(e, key, result);
    }
  } catch (const std::logic_error&) {
    // Counted fallback: the tree is rebuilt from the shadows still inserted.
    rebuild();
    RemoveResult rebuilt;
    rebuilt.found = true;
    rebuilt.rebuilt = true;
    rebuilt.changedCells = cells();
    rebuilt.newVertices = vertices();
    return rebuilt;
  }
  // Handles made and unmade within this removal are neither new nor removed.
  auto& created = result.newVertices;
  auto& removed = result.removedVertices;
  std::sort(created.begin(), created.end());
  created.erase(std::unique(created.begin(), created.end()), created.end());
  removed.erase(std::remove_if(removed.begin(), removed.end(), [&](VertexId v) { return v.index >= firstVertex; }),
                removed.end());
  created.erase(std::remove_if(created.begin(), created.end(), [&](VertexId v) { return !mesh_.vertex(v).alive; }),
                created.end());
  std::sort(result.changedCells.begin(), result.changedCells.end());
  result.changedCells.erase(std::unique(result.changedCells.begin(), result.changedCells.end()),
                            result.changedCells.end());
  return result;
}

}  // namespace penumbra
