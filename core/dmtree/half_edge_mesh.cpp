#include "core/dmtree/half_edge_mesh.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra {

Line2 Line2::rightOf(const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const Vec2 n = Vec2{d.y, -d.x} / glm::length(d);
  return Line2{n, -glm::dot(n, a)};
}

namespace {
std::atomic<uint64_t> meshClock{0};
}  // namespace

void HalfEdgeMesh::setOccluders(CellId c, const OccluderList& list) {
  touch(c);
  const OccluderListPool::Handle held = lists_.intern(list);  // before the release: `list` may be c's own
  lists_.release(cells_[c.index].occluders);
  cells_[c.index].occluders = held;
}

uint64_t HalfEdgeMesh::stampNow() { return meshClock.load(std::memory_order_relaxed); }
uint64_t HalfEdgeMesh::nextStamp() { return meshClock.fetch_add(1, std::memory_order_relaxed) + 1; }

VertexId HalfEdgeMesh::addVertex(const Vec2& p) {
  positions_.push_back(p);
  outs_.push_back(HalfEdgeId());
  ++liveVertices_;
  return VertexId(static_cast<uint32_t>(positions_.size() - 1));
}

void HalfEdgeMesh::killVertex(VertexId v) {
  outs_[v.index] = HalfEdgeId();
  --liveVertices_;
}

HalfEdgeId HalfEdgeMesh::addEdgePair() {
  halfEdges_.emplace_back();
  halfEdges_.emplace_back();
  edgeNodes_.emplace_back();
  liveHalfEdges_ += 2;
  return HalfEdgeId(static_cast<uint32_t>(halfEdges_.size() - 2));
}

CellId HalfEdgeMesh::reset(const Polygon2& receiver, double eps) {
  positions_.clear();
  outs_.clear();
  halfEdges_.clear();
  edgeNodes_.clear();
  cells_.clear();
  lists_.clear();
  liveVertices_ = liveHalfEdges_ = liveCells_ = 0;
  Polygon2 ring;
  for (const Vec2& p : receiver)
    if (ring.empty() || glm::length(p - ring.back()) > eps) ring.push_back(p);
  while (ring.size() > 1 && glm::length(ring.front() - ring.back()) <= eps) ring.pop_back();
  if (ring.size() < 3 || !(signedArea(ring) > 0))
    throw std::invalid_argument("DM-tree receiver must be a convex CCW polygon with positive area");
  const size_t n = ring.size();
  cells_.push_back(Cell{});
  ++liveCells_;
  const CellId c(0);
  for (size_t i = 0; i < n; ++i) addVertex(ring[i]);
  for (size_t i = 0; i < n; ++i) addEdgePair();
  // Pair i: inner half-edge 2i runs v_i → v_{i+1} in the cell; its twin runs back outside.
  for (size_t i = 0; i < n; ++i) {
    const size_t next = (i + 1) % n, prev = (i + n - 1) % n;
    HalfEdge& in = halfEdges_[2 * i];
    in.origin = VertexId(static_cast<uint32_t>(i));
    in.next = HalfEdgeId(static_cast<uint32_t>(2 * next));
    in.cell = c;
    HalfEdge& out = halfEdges_[2 * i + 1];
    out.origin = VertexId(static_cast<uint32_t>(next));
    out.next = HalfEdgeId(static_cast<uint32_t>(2 * prev + 1));
    outs_[i] = HalfEdgeId(static_cast<uint32_t>(2 * i));
  }
  cells_[0].edge = HalfEdgeId(0);
  touch(c);
  return c;
}

std::vector<HalfEdgeId> HalfEdgeMesh::loop(CellId c) const {
  std::vector<HalfEdgeId> out;
  out.reserve(8);  // most cells have a handful of edges: one allocation, not four
  loopInto(c, out);
  return out;
}

void HalfEdgeMesh::loopInto(CellId c, std::vector<HalfEdgeId>& out) const {
  out.clear();
  const HalfEdgeId start = cell(c).edge;
  HalfEdgeId h = start;
  do {
    out.push_back(h);
    if (out.size() > halfEdges_.size()) throw std::logic_error("DM-tree: cell loop does not close");
    h = halfEdge(h).next;
  } while (h != start);
}

Polygon2 HalfEdgeMesh::polygon(CellId c) const {
  Polygon2 out;
  for (HalfEdgeId h : loop(c)) out.push_back(vertex(halfEdge(h).origin).position);
  return out;
}

HalfEdgeId HalfEdgeMesh::prev(HalfEdgeId h) const {
  HalfEdgeId in = twin(h);  // ends at h's origin
  for (size_t steps = 0; halfEdge(in).next != h; ++steps) {
    in = twin(halfEdge(in).next);  // the next one ending there, counter-clockwise
    if (steps > halfEdges_.size()) throw std::logic_error("DM-tree: vertex star does not close");
  }
  return in;
}

std::vector<CellId> HalfEdgeMesh::cellsAround(VertexId v) const {
  std::vector<CellId> out;
  out.reserve(8);  // most vertices touch 2 to 6 cells
  const HalfEdgeId start = vertex(v).out;
  HalfEdgeId h = start;
  size_t steps = 0;
  do {
    if (halfEdge(h).cell.is_valid()) out.push_back(halfEdge(h).cell);
    h = halfEdge(twin(h)).next;  // next half-edge leaving v, counter-clockwise
    if (++steps > halfEdges_.size()) throw std::logic_error("DM-tree: vertex star does not close");
  } while (h != start);
  // Clockwise from start's cell, as callers always had them (illumination reads front()).
  std::reverse(out.begin() + (halfEdge(start).cell.is_valid() ? 1 : 0), out.end());
  return out;
}

HalfEdgeMesh::CutPlan HalfEdgeMesh::planCut(CellId c, const Line2& line, double eps) const {
  CutPlan plan;
  plan.cell = c;
  // Called for every cell a new line meets: the thread's scratch arrays, not three allocations.
  thread_local std::vector<HalfEdgeId> edges;
  thread_local std::vector<double> d;
  thread_local std::vector<int> s;
  loopInto(c, edges);
  const size_t m = edges.size();
  d.resize(m);
  s.resize(m);
  bool anyFront = false, anyBack = false;
  double sum = 0;
  for (size_t i = 0; i < m; ++i) {
    d[i] = line.distance(vertex(halfEdge(edges[i]).origin).position);
    s[i] = d[i] > eps ? 1 : (d[i] < -eps ? -1 : 0);
    anyFront |= s[i] > 0;
    anyBack |= s[i] < 0;
    sum += d[i];
  }
  if (!anyFront || !anyBack) {
    plan.side = anyFront ? 1 : (anyBack ? -1 : (sum >= 0 ? 1 : -1));
    return plan;
  }
  // Vertices on the line between two vertices of the same side belong to that side
  // (only a numerically bent loop has them).
  for (size_t i = 0; i < m; ++i) {
    if (s[i] != 0) continue;
    int before = 0, after = 0;
    for (size_t k = 1; k < m && !before; ++k) before = s[(i + m - k) % m];
    for (size_t k = 1; k < m && !after; ++k) after = s[(i + k) % m];
    if (before == after) s[i] = before;
  }
  int exits = 0, entries = 0;
  for (size_t i = 0; i < m; ++i) {
    if (s[i] == 0 || s[(i + 1) % m] == s[i]) continue;
    // A run from side s[i] to the other side, through vertices on the line.
    size_t j = (i + 1) % m;
    size_t best = m;
    while (s[j] == 0) {
      if (best == m || std::abs(d[j]) < std::abs(d[best])) best = j;
      j = (j + 1) % m;
    }
    CutEnd end;
    if (best == m) {
      const Vec2 p = vertex(halfEdge(edges[i]).origin).position;
      const Vec2 q = vertex(halfEdge(edges[j]).origin).position;
      end.edge = edges[i];
      end.split = true;
      end.point = p + (d[i] / (d[i] - d[j])) * (q - p);
    } else {
      end.edge = edges[best];
      end.point = vertex(halfEdge(edges[best]).origin).position;
    }
    if (s[i] > 0) {
      plan.exit = end;
      ++exits;
    } else {
      plan.entry = end;
      ++entries;
    }
  }
  if (exits != 1 || entries != 1) throw std::logic_error("DM-tree: a line crosses a cell loop more than twice");
  return plan;
}

VertexId HalfEdgeMesh::splitEdge(HalfEdgeId h, const Vec2& p) {
  const HalfEdgeId t = twin(h);
  const VertexId b = halfEdge(t).origin;
  const HalfEdgeId hn = halfEdge(h).next, tp = prev(t);
  const VertexId v = addVertex(p);
  const HalfEdgeId n = addEdgePair();
  const HalfEdgeId nt = twin(n);
  HalfEdge& hN = halfEdges_[n.index];
  edgeNodes_[n.index >> 1] = this->node(h);  // the new pair continues h's edge
  hN.origin = v;
  hN.cell = halfEdges_[h.index].cell;
  hN.next = hn;
  HalfEdge& hNT = halfEdges_[nt.index];
  hNT.origin = b;
  hNT.cell = halfEdges_[t.index].cell;
  hNT.next = t;
  halfEdges_[h.index].next = n;
  halfEdges_[tp.index].next = nt;
  halfEdges_[t.index].origin = v;
  outs_[v.index] = n;
  if (outs_[b.index] == t) outs_[b.index] = nt;
  for (HalfEdgeId side : {h, t})
    if (const CellId c = halfEdges_[side.index].cell; c.is_valid()) touch(c);
  return v;
}

HalfEdgeMesh::CutResult HalfEdgeMesh::applyCut(const CutPlan& plan, NodeId node) {
  if (plan.side != 0) throw std::logic_error("DM-tree: applyCut on a cell the line does not cross");
  CutResult result;
  auto end = [&](const CutEnd& e) {
    if (!e.split) return e.edge;
    result.newVertices.push_back(splitEdge(e.edge, e.point));
    return halfEdge(e.edge).next;
  };
  const HalfEdgeId hu = end(plan.entry);
  const HalfEdgeId hw = end(plan.exit);
  const VertexId u = halfEdge(hu).origin, w = halfEdge(hw).origin;
  const HalfEdgeId pu = prev(hu), pw = prev(hw);
  const HalfEdgeId e = addEdgePair(), et = twin(e);
  halfEdges_[e.index].origin = u;
  edgeNodes_[e.index >> 1] = node;
  halfEdges_[et.index].origin = w;
  // Front loop: u … w then w→u; back loop: w … u then u→w.
  halfEdges_[pw.index].next = et;
  halfEdges_[et.index].next = hu;
  halfEdges_[pu.index].next = e;
  halfEdges_[e.index].next = hw;

  const CellId front = plan.cell;
  cells_.push_back(Cell{e, NodeId(), cells_[front.index].occluders, true});
  lists_.retain(cells_[front.index].occluders);
  ++liveCells_;
  const CellId back(static_cast<uint32_t>(cells_.size() - 1));
  cells_[front.index].edge = et;
  for (HalfEdgeId h : loop(front)) halfEdges_[h.index].cell = front;
  for (HalfEdgeId h : loop(back)) halfEdges_[h.index].cell = back;
  touch(front);
  touch(back);
  result.front = front;
  result.back = back;
  result.chord = e;
  return result;
}

bool HalfEdgeMesh::dissolvable(VertexId v, double eps) const {
  const HalfEdgeId e2 = vertex(v).out;
  const HalfEdgeId e1 = prev(e2);
  const HalfEdgeId t1 = twin(e1), t2 = twin(e2);
  if (halfEdge(t2).next != t1) return false;  // more than two edges at v
  if (node(e1) != node(e2)) return false;
  const Vec2 a = vertex(halfEdge(e1).origin).position, b = vertex(destination(e2)).position;
  if (halfEdge(e1).origin == destination(e2)) return false;
  if (std::abs(lineDistance(a, b, vertex(v).position)) > eps) return false;
  // Neither loop may drop below a triangle.
  for (HalfEdgeId h : {e2, t2}) {
    size_t count = 0;
    HalfEdgeId k = h;
    do {
      ++count;
      k = halfEdge(k).next;
    } while (k != h && count < 4);
    if (count < 4) return false;
  }
  return true;
}

void HalfEdgeMesh::dissolveVertex(VertexId v) {
  const HalfEdgeId e2 = vertex(v).out;
  const HalfEdgeId e1 = prev(e2);
  const HalfEdgeId t1 = twin(e1), t2 = twin(e2);
  const VertexId b = destination(e2);
  const HalfEdgeId e2n = halfEdge(e2).next, t2p = prev(t2);
  halfEdges_[e1.index].next = e2n;
  halfEdges_[t1.index].origin = b;
  halfEdges_[t2p.index].next = t1;
  if (outs_[b.index] == t2) outs_[b.index] = t1;
  for (auto [dead, keep] : {std::pair{e2, e1}, std::pair{t2, t1}}) {
    const CellId c = halfEdge(dead).cell;
    if (c.is_valid()) touch(c);
    if (c.is_valid() && cells_[c.index].edge == dead) cells_[c.index].edge = keep;
    kill(dead);
  }
  liveHalfEdges_ -= 2;
  killVertex(v);
}

std::vector<VertexId> HalfEdgeMesh::mergeCells(CellId keep, CellId drop, double eps) {
  const std::vector<HalfEdgeId> edges = loop(keep);
  const size_t m = edges.size();
  auto shared = [&](size_t i) { return halfEdge(twin(edges[i % m])).cell == drop; };
  size_t first = m, count = 0;
  for (size_t i = 0; i < m; ++i) {
    if (shared(i)) ++count;
    if (shared(i) && !shared(i + m - 1)) first = i;
  }
  if (first == m || count == m) throw std::logic_error("DM-tree: merged cells are not adjacent");
  std::vector<HalfEdgeId> chain;
  for (size_t i = first; shared(i); ++i) chain.push_back(edges[i % m]);
  if (chain.size() != count) throw std::logic_error("DM-tree: merged cells share a broken boundary");

  const HalfEdgeId h1 = chain.front(), hk = chain.back();
  const HalfEdgeId t1 = twin(h1), tk = twin(hk);
  const HalfEdgeId p = prev(h1), q = halfEdge(hk).next;
  const HalfEdgeId pp = prev(tk), qq = halfEdge(t1).next;
  const VertexId u = halfEdge(h1).origin, w = halfEdge(q).origin;
  for (HalfEdgeId h : loop(drop))
    if (halfEdge(twin(h)).cell != keep) halfEdges_[h.index].cell = keep;
  halfEdges_[p.index].next = qq;
  halfEdges_[pp.index].next = q;
  std::vector<VertexId> removed;
  for (size_t i = 0; i < chain.size(); ++i) {
    if (i > 0) {
      const VertexId inner = halfEdge(chain[i]).origin;
      killVertex(inner);
      removed.push_back(inner);
    }
    kill(chain[i]);
    kill(twin(chain[i]));
    liveHalfEdges_ -= 2;
  }
  if (!halfEdge(vertex(u).out).alive()) outs_[u.index] = qq;
  if (!halfEdge(vertex(w).out).alive()) outs_[w.index] = q;
  cells_[keep.index].edge = p;
  cells_[drop.index].alive = false;
  lists_.release(cells_[drop.index].occluders);
  cells_[drop.index].occluders = OccluderListPool::kEmpty;
  touch(keep);
  touch(drop);
  --liveCells_;
  for (VertexId v : {u, w})
    if (dissolvable(v, eps)) {
      dissolveVertex(v);
      removed.push_back(v);
    }
  return removed;
}

void HalfEdgeMesh::validate(double eps, double receiverArea) const {
  auto fail = [](const std::string& what) { throw std::logic_error("DM-tree mesh: " + what); };
  size_t liveH = 0, liveV = 0, liveC = 0;
  // Each live half-edge must be the next of at most one (so, counting, of exactly one):
  // then prev() is well defined and every turn around a vertex closes.
  std::vector<char> isNext(halfEdges_.size(), 0);
  for (uint32_t i = 0; i < halfEdges_.size(); ++i) {
    const HalfEdge& h = halfEdges_[i];
    if (!h.alive()) continue;
    ++liveH;
    const HalfEdgeId id(i);
    const HalfEdge& t = halfEdge(twin(id));
    if (!t.alive()) fail("half-edge " + std::to_string(i) + " has a dead twin");
    if (!halfEdge(h.next).alive()) fail("half-edge " + std::to_string(i) + " has a dead next");
    if (isNext[h.next.index]++) fail("half-edge " + std::to_string(h.next.index) + " is the next of two");
    if (halfEdge(h.next).origin != t.origin) fail("next does not start where half-edge ends");
    if (halfEdge(h.next).cell != h.cell) fail("loop changes cell");
    if (!h.origin.is_valid() || !vertex(h.origin).alive) fail("half-edge from a dead vertex");
    if (h.cell == t.cell) fail("both sides of an edge in one cell");
    if (h.cell.is_valid() && !cell(h.cell).alive) fail("half-edge in a dead cell");
    if (!h.cell.is_valid() && node(HalfEdgeId(i)).is_valid()) fail("outer half-edge made by a tree node");
    if (!(glm::length(vertex(h.origin).position - vertex(t.origin).position) > eps))
      fail("edge shorter than the tolerance");
  }
  for (uint32_t i = 0; i < outs_.size(); ++i) {
    const HalfEdgeId out = outs_[i];
    if (!out.is_valid()) continue;  // dead (a live vertex without one fails the count below)
    ++liveV;
    if (!halfEdge(out).alive() || halfEdge(out).origin != VertexId(i))
      fail("vertex " + std::to_string(i) + " has a bad out half-edge");
  }
  size_t inLoops = 0;
  double total = 0;
  for (uint32_t i = 0; i < cells_.size(); ++i) {
    if (!cells_[i].alive) continue;
    ++liveC;
    const CellId c(i);
    if (!halfEdge(cells_[i].edge).alive()) fail("cell with a dead half-edge");
    const std::vector<HalfEdgeId> edges = loop(c);
    inLoops += edges.size();
    for (HalfEdgeId h : edges)
      if (halfEdge(h).cell != c) fail("loop of cell " + std::to_string(i) + " leaves the cell");
    const Polygon2 poly = polygon(c);
    const size_t m = poly.size();
    if (m < 3) fail("cell with fewer than three vertices");
    for (size_t k = 0; k < m; ++k)
      if (lineDistance(poly[k], poly[(k + 1) % m], poly[(k + 2) % m]) < -eps)
        fail("cell " + std::to_string(i) + " is not convex CCW");
    const double area = signedArea(poly);
    if (!(area > 0)) fail("cell " + std::to_string(i) + " has no positive area");
    total += area;
  }
  std::vector<size_t> holders;
  for (const Cell& cell : cells_) {
    if (!cell.alive) {
      if (cell.occluders != OccluderListPool::kEmpty) fail("a dead cell holds an occluder list");
      continue;
    }
    if (cell.occluders >= holders.size()) holders.resize(cell.occluders + 1);
    ++holders[cell.occluders];
  }
  lists_.validate(holders);
  size_t outer = 0;
  for (const HalfEdge& h : halfEdges_)
    if (h.alive() && !h.cell.is_valid()) ++outer;
  if (inLoops + outer != liveH) fail("half-edges outside every loop");
  if (liveH != liveHalfEdges_ || liveV != liveVertices_ || liveC != liveCells_) fail("live counters drift");
  if (std::abs(total - receiverArea) > 1e-12 * receiverArea)
    fail("cells do not tile the receiver: " + std::to_string(total) + " vs " + std::to_string(receiverArea));
}

void HalfEdgeMesh::shrinkToFit() {
  positions_.shrink_to_fit();
  outs_.shrink_to_fit();
  halfEdges_.shrink_to_fit();
  edgeNodes_.shrink_to_fit();
  cells_.shrink_to_fit();
  lists_.shrinkToFit();
}

}  // namespace penumbra
