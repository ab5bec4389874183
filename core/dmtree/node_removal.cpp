// DmTree::removeOccluder: deleting one occluder's list entries and tree nodes (paper
// §3.1): unlink a node's edge, extend the basis subtree's dangling edges across the other
// side, insert the other subtree split only where they cross it, condense what no
// longer separates.
#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "core/dmtree/dm_tree.h"

namespace penumbra {

namespace {

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

// Where a convex region lies against a line: +1 / -1 wholly in front / behind (within
// eps), 0 across it. Classifying the region's corners decides for every cell inside it.
int sideOf(const Polygon2& region, const Line2& line, double eps) {
  bool front = false, back = false;
  for (const Vec2& p : region) {
    const double d = line.distance(p);
    front |= d > eps;
    back |= d < -eps;
  }
  return front && back ? 0 : back ? -1 : 1;
}

// The two sides of a region cut by a line: {right = front, left = back}.
Split2 splitRegion(const Polygon2& region, const Line2& line, double eps) {
  const Vec2 a = -line.offset * line.normal;
  return splitByLine(region, a, a + along(line), eps);
}

}  // namespace

void DmTree::killNode(NodeId n) {
  DmNode& d = nodes_[n.index];
  d.alive = false;
  d.makeInternal(NodeId(), NodeId());  // no cell, no children
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
  const Line2& line = segment(n).line;
  const double dp = line.distance(p), dq = line.distance(q);
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
    const Split2 split = splitRegion(region, segment(p).line, tolerance_.length());
    region = node(p).front == child ? split.right : split.left;  // front = right of a→b
  }
  return region;
}

bool DmTree::chordOf(NodeId n, double& lo, double& hi) const {
  // The cells below n tile its region, so the chord is the union of their chords;
  // walking a few cells beats splitting the receiver by every ancestor's line.
  constexpr size_t kMaxCells = 64;
  const double eps = tolerance_.length();
  const Line2& line = segment(n).line;
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
    if (!chordExtent(line, mesh_.polygon(node(leaf).cell()), eps, a, b)) continue;
    lo = std::min(lo, a);
    hi = std::max(hi, b);
  }
  return hi - lo > eps;
}

// A still-inserted occluder's discontinuity overlapping n's chord [lo, hi] (positions
// along n's line): the edge must stay although n's own generator is gone.
const std::vector<KeptSegment>& DmTree::keptSegments(const OccluderKey& key, const SingleShadow& shadow) {
  const auto it = keptSegments_.find(key);
  if (it != keptSegments_.end()) return it->second;
  return keptSegments_.emplace(key, buildSingleTree(shadow, tolerance_).segments()).first->second;
}

const KeptSegment* DmTree::liveSegmentOn(NodeId n, double lo, double hi, const std::vector<OccluderKey>& keys,
                                         OccluderKey* owner) {
  const double eps = tolerance_.length();
  const Line2& line = segment(n).line;
  const Vec2 dir = along(line);
  for (const OccluderKey& key : keys) {
    const auto it = inserted_.find(key);
    if (it == inserted_.end()) continue;
    for (const KeptSegment& s : keptSegments(key, it->second.shadow)) {
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

// Step 2 (the other side): the piece of a basis leaf's cell is cut by the lines of the
// subtree t grafted in its place until it reaches a leaf, then joins that leaf's cell
// across the deleted edge. The joined cell keeps the list of the part holding its
// centroid (the two agree unless the deleted edge separated a numerical disagreement).
void DmTree::extendInto(NodeId n, CellId piece, const Line2& deleted, std::vector<NodeId>& extended,
                        RemoveResult& result) {
  const double eps = tolerance_.length();
  if (node(n).isLeaf()) {
    const CellId keep = node(n).cell();
    const OccluderList pieceList = mesh_.occluders(piece);  // a copy: the merge frees piece's
    const double pieceSide = deleted.distance(areaCentroid(mesh_.polygon(piece)));
    const std::vector<VertexId> removed = mesh_.mergeCells(keep, piece, eps);
    result.removedVertices.insert(result.removedVertices.end(), removed.begin(), removed.end());
    result.changedCells.push_back(keep);
    if (pieceSide * deleted.distance(areaCentroid(mesh_.polygon(keep))) > 0 &&
        mesh_.occluders(keep) != pieceList)
      mesh_.setOccluders(keep, pieceList);
    return;
  }
  const HalfEdgeMesh::CutPlan plan = mesh_.planCut(piece, segment(n).line, eps);
  if (plan.side > 0) return extendInto(node(n).front, piece, deleted, extended, result);
  if (plan.side < 0) return extendInto(node(n).back, piece, deleted, extended, result);
  const HalfEdgeMesh::CutResult cut = mesh_.applyCut(plan, n);
  result.newVertices.insert(result.newVertices.end(), cut.newVertices.begin(), cut.newVertices.end());
  segmentForWrite(n).partial = true;
  extended.push_back(n);
  const NodeId front = node(n).front, back = node(n).back;
  extendInto(front, cut.front, deleted, extended, result);
  extendInto(back, cut.back, deleted, extended, result);
}

// A copy of internal node n (same line and generator) for the other side of a split.
// Both are remembered by generator: either may now lie outside that occluder's
// penumbra, where removing it would not look.
NodeId DmTree::copyOf(NodeId n) {
  DmNode copy = node(n);
  copy.front = copy.back = copy.parent = NodeId();
  NodeSegment seg = segment(n);
  seg.partial = seg.copy = true;
  copy.segment = addSegment(seg);
  nodes_.push_back(copy);
  ++liveNodes_;
  const NodeId id(static_cast<uint32_t>(nodes_.size() - 1));
  std::vector<NodeId>& split = splitNodes_[owners_[seg.owner]];
  split.push_back(n);
  split.push_back(id);
  return id;
}

// The mesh edges of `from` along its line among the cells below `under` now belong to `to`.
void DmTree::relabelEdges(NodeId from, NodeId to, NodeId under, const Polygon2& region) {
  double lo, hi;
  const Line2& line = segment(from).line;
  if (!chordExtent(line, region, tolerance_.length(), lo, hi)) return;
  const Vec2 origin = -line.offset * line.normal, dir = along(line);
  std::vector<NodeId> leaves;
  leavesAlong(under, origin + lo * dir, origin + hi * dir, leaves);
  for (NodeId leaf : leaves)
    for (HalfEdgeId h : mesh_.loop(node(leaf).cell()))
      if (mesh_.node(h) == from) mesh_.relabel(h, to);
}

// Step 3: splits subtree t (covering `region`) by the line of basis node `cutter`. Only
// cells the line crosses are cut; a subtree whose region lies on one side goes whole,
// found by classifying its region's corners. A node needed on both sides is copied.
DmTree::SplitTree DmTree::partition(NodeId t, NodeId cutter, const Polygon2& region,
                                    RemoveResult& result) {
  const double eps = tolerance_.length();
  const Line2 line = segment(cutter).line;
  const int side = sideOf(region, line, eps);
  if (side > 0) return {t, NodeId()};
  if (side < 0) return {NodeId(), t};
  if (node(t).isLeaf()) {
    const HalfEdgeMesh::CutPlan plan = mesh_.planCut(node(t).cell(), line, eps);
    if (plan.side > 0) return {t, NodeId()};
    if (plan.side < 0) return {NodeId(), t};
    const HalfEdgeMesh::CutResult cut =
        mesh_.applyCut(plan, cutter);  // the front part keeps t's cell
    result.newVertices.insert(result.newVertices.end(), cut.newVertices.begin(),
                              cut.newVertices.end());
    result.changedCells.push_back(cut.front);
    result.changedCells.push_back(cut.back);
    return {t, addNode(NodeId(), cut.back)};
  }
  const Line2 own = segment(t).line;
  const NodeId tFront = node(t).front, tBack = node(t).back;
  const Split2 halves = splitRegion(region, own, eps);
  const SplitTree f = partition(tFront, cutter, halves.right, result);
  const SplitTree b = partition(tBack, cutter, halves.left, result);
  const bool frontNeedsT = f.front.is_valid() && b.front.is_valid();
  const bool backNeedsT = f.back.is_valid() && b.back.is_valid();
  NodeId backNode = t;
  if (frontNeedsT && backNeedsT) {
    backNode = copyOf(t);
    ++result.nodesSplit;
  }
  auto join = [&](NodeId n, NodeId x, NodeId y) {
    if (!x.is_valid()) return y;
    if (!y.is_valid()) return x;
    DmNode& d = nodes_[n.index];
    d.front = x;
    d.back = y;
    segmentForWrite(n).partial = true;
    nodes_[x.index].parent = n;
    nodes_[y.index].parent = n;
    return n;
  };
  const SplitTree out{join(t, f.front, b.front), join(backNode, f.back, b.back)};
  if (backNode != t) {
    relabelEdges(t, backNode, out.back, splitRegion(region, line, eps).left);
  } else if (!frontNeedsT && !backNeedsT) {
    // t's line separated the same cells as the cutter's (the two are collinear here).
    relabelEdges(t, cutter, tFront, region);
    relabelEdges(t, cutter, tBack, region);
    killNode(t);
  }
  return out;
}

// Step 3: basis node n takes b's subtree t (covering `region`, on b's side of the
// deleted edge). A basis line crossing the region splits t (the line is extended); at
// a basis leaf, t takes the leaf's place and the leaf's cell joins t's cells.
void DmTree::mergeInto(NodeId n, NodeId t, const Polygon2& region, const Line2& deleted,
                       std::vector<NodeId>& extended, RemoveResult& result) {
  const double eps = tolerance_.length();
  if (node(n).isLeaf()) {
    const NodeId parent = node(n).parent;
    nodes_[t.index].parent = parent;
    if (!parent.is_valid())
      root_ = t;
    else if (node(parent).front == n)
      nodes_[parent.index].front = t;
    else
      nodes_[parent.index].back = t;
    const CellId piece = node(n).cell();
    killNode(n);
    extendInto(t, piece, deleted, extended, result);
    return;
  }
  const Line2 line = segment(n).line;
  const NodeId front = node(n).front, back = node(n).back;
  const int side = sideOf(region, line, eps);
  if (side > 0) return mergeInto(front, t, region, deleted, extended, result);
  if (side < 0) return mergeInto(back, t, region, deleted, extended, result);
  const SplitTree parts = partition(t, n, region, result);
  segmentForWrite(n).partial = true;
  extended.push_back(n);
  const Split2 halves = splitRegion(region, line, eps);
  if (parts.front.is_valid())
    mergeInto(front, parts.front, halves.right, deleted, extended, result);
  if (parts.back.is_valid()) mergeInto(back, parts.back, halves.left, deleted, extended, result);
}

// Removes n's split if its two cells are leaves with equal lists and its edge carries
// no live discontinuity (paper: "the subtrees created are condensed", edge 14b). Only
// occluders listed in the two cells can have a segment on the edge.
void DmTree::condenseLeafPair(NodeId n, RemoveResult& result) {
  const DmNode& d = node(n);
  if (!d.alive || d.isLeaf() || !node(d.front).isLeaf() || !node(d.back).isLeaf()) return;
  const CellId keep = node(d.front).cell(), drop = node(d.back).cell();
  if (mesh_.cell(keep).occluders != mesh_.cell(drop).occluders) return;  // interned: equal lists, equal handles
  std::vector<OccluderKey> keys;
  for (const OccluderEntry& entry : mesh_.occluders(keep))
    keys.push_back({entry.light, entry.face});
  double lo, hi;
  if (chordOf(n, lo, hi) && liveSegmentOn(n, lo, hi, keys, nullptr)) return;
  const std::vector<VertexId> removed = mesh_.mergeCells(keep, drop, tolerance_.length());
  result.removedVertices.insert(result.removedVertices.end(), removed.begin(), removed.end());
  result.changedCells.push_back(keep);
  const NodeId front = d.front, back = d.back;
  killNode(front);
  killNode(back);
  NodeSegment& m = segmentForWrite(n);
  nodes_[n.index].makeLeaf(keep);
  m.partial = m.orphan = false;
  mesh_.setLeaf(keep, n);
  if (owners_[m.owner] == removing_)
    ++(m.copy ? result.copiesRemoved : result.nodesRemoved);
  else ++result.nodesCondensed;
}

void DmTree::deleteNode(NodeId e, const OccluderKey& key, RemoveResult& result) {
  const double eps = tolerance_.length();
  const NodeId front = node(e).front, back = node(e).back;
  const Line2 deletedLine = segment(e).line;
  // e's region: its chord, and later b's side of it.
  const Polygon2 region = regionOf(e);
  double lo, hi;
  if (!chordExtent(deletedLine, region, eps, lo, hi)) throw std::logic_error("DM-tree: a node without an edge");
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
    for (const OccluderEntry& entry : mesh_.occluders(node(leaf).cell())) keySet.insert({entry.light, entry.face});
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
  OccluderKey liveOwner;
  if (const KeptSegment* s = liveSegmentOn(e, lo, hi, sortedKeys(), &liveOwner)) {
    NodeSegment& d = segmentForWrite(e);
    d.owner = ownerIndex(liveOwner);
    d.kind = s->kind;
    d.partial = true;
    ++result.nodesRelabeled;
    return;
  }
  if (node(front).isLeaf() && node(back).isLeaf() &&
      mesh_.cell(node(front).cell()).occluders != mesh_.cell(node(back).cell()).occluders) {
    // Different lists but no live segment between them: a numerical disagreement;
    // keep the edge rather than give one side the wrong list.
    segmentForWrite(e).orphan = true;
    ++result.nodesKept;
    return;
  }

  // Step 1 (counting): dangling edges are the other edges ending on e's edge.
  size_t dangling[2] = {0, 0};
  for (int side = 0; side < 2; ++side)
    for (NodeId leaf : along[side]) {
      const std::vector<HalfEdgeId> edges = mesh_.loop(node(leaf).cell());
      for (size_t i = 0; i < edges.size(); ++i) {
        if (mesh_.node(edges[i]) != e) continue;
        const VertexId v = mesh_.halfEdge(edges[i]).origin;
        const Vec2 x = mesh_.vertex(v).position;
        const double t = glm::dot(x, dir);
        const NodeId other = mesh_.node(edges[(i + edges.size() - 1) % edges.size()]);  // the edge before
        if (other != e && t > lo + eps && t < hi - eps) ++dangling[side];  // not at the edge's ends
      }
    }
  // Live internal nodes per side (the removed occluder's own go anyway), counted on both
  // sides in turn and only until the choice is certain: the side to insert is usually
  // small, the other may be most of the tree.
  struct Count {
    std::vector<NodeId> stack;
    size_t size = 0;
    bool done() const { return stack.empty(); }
  };
  Count count[2] = {{{front}}, {{back}}};
  auto step = [&](Count& c) {
    const NodeId n = c.stack.back();
    const DmNode& d = node(n);
    c.stack.pop_back();
    if (d.isLeaf()) return;
    if (owner(n) != key) ++c.size;
    c.stack.push_back(d.front);
    c.stack.push_back(d.back);
  };
  // cost(side as basis) = (D_side + 1)·size_other; an unfinished count bounds its side's size
  // from below. A finished side is surely the one to insert once keeping it as basis
  // would cost more: (D_mine + 1)·size_other > (D_other + 1)·size_mine.
  auto certain = [&] {
    for (int side = 0; side < 2; ++side) {
      const Count &mine = count[side], &other = count[1 - side];
      if (mine.done() && (dangling[side] + 1) * other.size > (dangling[1 - side] + 1) * mine.size) return true;
    }
    return count[0].done() && count[1].done();
  };
  // Past kCountLimit nodes a side both are large: the partial counts (equal then) leave
  // the choice to the dangling edges.
  constexpr size_t kCountLimit = 1024;
  for (size_t steps = 0; steps < kCountLimit && !certain(); ++steps) {
    if (!count[0].done()) step(count[0]);
    if (!count[1].done()) step(count[1]);
  }
  // Step 2: the basis a minimises E[cost_a] = (D_a + 1)·size_b (the paper's D_a·size_b;
  // the +1 counts inserting b even when a has nothing to extend). An unfinished count
  // is a lower bound: when the choice was certain it only favours the same side.
  const size_t size[2] = {count[0].size, count[1].size};
  const bool frontBasis = (dangling[0] + 1) * size[1] <= (dangling[1] + 1) * size[0];
  const NodeId a = frontBasis ? front : back, b = frontBasis ? back : front;
  // b's part of e's region, before e is unlinked.
  const Split2 halves = splitRegion(region, deletedLine, eps);
  const Polygon2 bRegion = frontBasis ? halves.left : halves.right;

  // Unlink e: a takes its place.
  const NodeId parent = node(e).parent;
  nodes_[a.index].parent = parent;
  if (!parent.is_valid()) root_ = a;
  else if (node(parent).front == e) nodes_[parent.index].front = a;
  else nodes_[parent.index].back = a;
  ++(segment(e).copy ? result.copiesRemoved : result.nodesRemoved);
  killNode(e);

  // Steps 2 and 3: a's dangling lines extend across b's region, splitting b's subtree
  // where they cross it; each of a's leaves along e takes its share of b.
  const size_t firstChanged = result.changedCells.size();
  std::vector<NodeId> extended;
  mergeInto(a, b, bRegion, deletedLine, extended, result);
  std::vector<CellId> check(result.changedCells.begin() + firstChanged, result.changedCells.end());
  for (const auto& side : along)
    for (NodeId leaf : side) check.push_back(node(leaf).cell());
  for (CellId c : check) {
    if (!c.is_valid() || !mesh_.cell(c).alive) continue;
    for (HalfEdgeId h : mesh_.loop(c))
      if (mesh_.node(h) == e)
        throw std::logic_error("DM-tree: an edge of a deleted node is left");
  }
  // Extended splits, deepest first (they were found top-down).
  for (auto it = extended.rbegin(); it != extended.rend(); ++it) condenseLeafPair(*it, result);
}

void DmTree::rebuild() {
  std::vector<std::pair<uint64_t, SingleShadow>> ordered;
  for (const auto& [key, entry] : inserted_) ordered.push_back({entry.sequence, entry.shadow});
  std::sort(ordered.begin(), ordered.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  inserted_.clear();
  nodes_.clear();
  segments_.clear();
  owners_.clear();
  ownerIndex_.clear();
  splitNodes_.clear();
  liveNodes_ = 0;
  const CellId c = mesh_.reset(receiver_, tolerance_.length());
  root_ = addNode(NodeId(), c);
  for (const auto& [sequence, shadow] : ordered) insert(shadow);
}

namespace {

struct Box2 {
  Vec2 lo{INFINITY}, hi{-INFINITY};
  explicit Box2(const Polygon2& polygon, double margin) {
    for (const Vec2& p : polygon) {
      lo = glm::min(lo, p - Vec2(margin));
      hi = glm::max(hi, p + Vec2(margin));
    }
  }
  bool overlaps(const Box2& o) const {
    return lo.x <= o.hi.x && o.lo.x <= hi.x && lo.y <= o.hi.y && o.lo.y <= hi.y;
  }
};

}  // namespace

size_t DmTree::culledOccluders() const {
  size_t n = 0;
  for (const auto& [key, entry] : inserted_) n += entry.culled;
  return n;
}

// A key culled behind `key` was inserted after it and culled somewhere its penumbra
// meets the umbra of `key` or of another key taken before it (their removal frees that
// umbra too). Boxes make this a superset: re-casting an occluder that did not need it
// costs time, never correctness.
std::vector<DmTree::OccluderKey> DmTree::culledBehind(const OccluderKey& key) const {
  const Inserted& removed = inserted_.at(key);
  if (!removed.culls()) return {};
  std::vector<std::pair<uint64_t, OccluderKey>> later;
  for (auto it = inserted_.lower_bound({key.first, FaceId{0, 0}}); it != inserted_.end() && it->first.first == key.first;
       ++it)
    if (it->second.culled && it->second.sequence > removed.sequence) later.push_back({it->second.sequence, it->first});
  if (later.empty()) return {};
  std::sort(later.begin(), later.end());
  const double eps = tolerance_.length();
  std::vector<Box2> freed{Box2(removed.shadow.umbra, eps)};
  std::vector<OccluderKey> out;
  for (const auto& [sequence, k] : later) {
    const Inserted& entry = inserted_.at(k);
    const Box2 reach(mergedPenumbra(entry), eps);
    if (std::none_of(freed.begin(), freed.end(), [&](const Box2& b) { return b.overlaps(reach); })) continue;
    out.push_back(k);
    if (!entry.shadow.umbra.empty()) freed.push_back(Box2(entry.shadow.umbra, eps));
  }
  return out;
}

RemoveResult DmTree::removeOccluder(uint32_t light, FaceId occluder) {
  RemoveResult result;
  const OccluderKey key{light, occluder};
  const auto it = inserted_.find(key);
  if (it == inserted_.end()) return result;
  struct ForgetKeptSegments {  // derived for this removal only: shadows change between removals
    std::map<OccluderKey, std::vector<KeptSegment>>& segments;
    ~ForgetKeptSegments() { segments.clear(); }
  } forget{keptSegments_};
  result.found = true;
  result.penumbra = mergedPenumbra(it->second);
  const std::vector<OccluderKey> recast = umbraCulling_ ? culledBehind(key) : std::vector<OccluderKey>{};
  std::vector<SingleShadow> shadows;
  for (const OccluderKey& k : recast) shadows.push_back(inserted_.at(k).shadow);
  const size_t firstVertex = mesh_.vertexSlots();
  const uint32_t firstCell = mesh_.cellSlots();
  try {
    for (auto k = recast.rbegin(); k != recast.rend(); ++k) removeOne(*k, result);
    removeOne(key, result);
    for (const SingleShadow& shadow : shadows) {
      const InsertResult added = insert(shadow);
      result.changedCells.insert(result.changedCells.end(), added.changedCells.begin(), added.changedCells.end());
      result.newVertices.insert(result.newVertices.end(), added.newVertices.begin(), added.newVertices.end());
    }
  } catch (const std::logic_error&) {
    // Counted fallback: the tree is rebuilt from the shadows still inserted, and the
    // culled ones this removal had taken out go back in.
    inserted_.erase(key);
    rebuild();
    for (const SingleShadow& shadow : shadows)
      if (!inserted_.count({shadow.light, shadow.occluder})) insert(shadow);
    RemoveResult rebuilt;
    rebuilt.found = true;
    rebuilt.rebuilt = true;
    rebuilt.penumbra = result.penumbra;
    rebuilt.changedCells = cells();
    rebuilt.newVertices = vertices();
    return rebuilt;
  }
  // A re-cast splits cells this removal reported: the pieces that did not gain its entry
  // changed too (a piece keeps the old handle, the other is new), so report every cell
  // made here.
  if (!recast.empty())
    for (uint32_t i = firstCell; i < mesh_.cellSlots(); ++i)
      if (mesh_.cell(CellId(i)).alive) result.changedCells.push_back(CellId(i));
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
  compactOwners();
  return result;
}

// Throws std::logic_error if a geometric step fails (the caller rebuilds).
void DmTree::removeOne(const OccluderKey& key, RemoveResult& result) {
  const auto it = inserted_.find(key);
  const Polygon2 penumbra = mergedPenumbra(it->second);
  inserted_.erase(it);
  const uint32_t light = key.first;  // copies, not a structured binding: clang cannot capture one
  const FaceId occluder = key.second;
  removing_ = key;
  // Its list entries: only cells under its penumbra can hold one.
  std::vector<CellId> covered;
  std::vector<NodeId> doomed;
  if (!penumbra.empty()) collectCells(root_, penumbra, covered, &key, &doomed);
  for (CellId c : covered) {
    const auto listed = [&](const OccluderEntry& e) { return e.light == light && e.face == occluder; };
    const OccluderList& held = mesh_.occluders(c);
    if (std::none_of(held.begin(), held.end(), listed)) continue;
    OccluderList& list = scratchList_;
    list = held;
    list.erase(std::remove_if(list.begin(), list.end(), listed), list.end());
    mesh_.setOccluders(c, list);
    result.changedCells.push_back(c);
  }
  // Its nodes, top-down, then those split by an extended edge (before or during this
  // removal; they may lie outside the penumbra), copies among them.
  std::reverse(doomed.begin(), doomed.end());
  for (size_t i = 0;; ++i) {
    if (i == doomed.size()) {
      const auto split = splitNodes_.find(key);
      if (split == splitNodes_.end()) break;
      for (NodeId n : split->second)  // a node split twice is listed twice
        if (std::find(doomed.begin(), doomed.end(), n) == doomed.end()) doomed.push_back(n);
      splitNodes_.erase(split);
      if (i == doomed.size()) break;
    }
    const NodeId e = doomed[i];
    const DmNode& d = node(e);
    if (!d.alive || d.isLeaf() || owner(e) != key) continue;
    deleteNode(e, key, result);
  }
}

}  // namespace penumbra
