// The winged-edge (half-edge) mesh of one receiver's DM-tree cells: vertices,
// half-edge pairs, convex CCW cells. Changed only by its owning DmTree; not thread-safe.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/dmtree/handles.h"
#include "core/dmtree/occluder_list.h"
#include "core/dmtree/occluder_list_pool.h"
#include "core/geom/convex2d.h"
#include "core/geom/vec.h"

namespace penumbra {

// An oriented line n·x + c = 0 with |n| = 1; "front" is n·x + c > 0.
struct Line2 {
  Vec2 normal{1.0, 0.0};
  double offset = 0;
  double distance(const Vec2& p) const { return glm::dot(normal, p) + offset; }
  // The line through a→b whose front is the right side of a→b.
  static Line2 rightOf(const Vec2& a, const Vec2& b);
};

class HalfEdgeMesh {
 public:
  // A vertex as read (vertex()): its position and out half-edge are kept in two arrays,
  // 20 bytes a vertex instead of 24; a dead vertex has no out half-edge.
  struct Vertex {
    Vec2 position{0.0};
    HalfEdgeId out;  // one half-edge leaving the vertex
    bool alive = true;
  };
  // 12 bytes: no prev (prev() finds it around the origin), no alive flag (a dead
  // half-edge is in no loop: its next is invalid) and no node (one per edge pair, see
  // node()). Meshes hold millions of them.
  struct HalfEdge {
    VertexId origin;
    HalfEdgeId next;
    CellId cell;  // invalid: outside the receiver
    bool alive() const { return next.is_valid(); }
  };
  static_assert(sizeof(HalfEdge) == 12);
  // 20 bytes: the list is a handle into the mesh's pool, the alive flag shares the
  // stamp's high word, and the stamp is kept in two 32-bit words (no 8-byte alignment).
  struct Cell {
    HalfEdgeId edge;  // one half-edge of the loop
    NodeId leaf;      // the BSP leaf holding this cell
    OccluderListPool::Handle occluders = OccluderListPool::kEmpty;
    bool alive : 1 = true;
    // When the cell last changed (loop, list, or death), on stampNow()'s clock. 63 bits
    // never wrap; 32 would within a few hundred large builds (5·10⁶ stamps each).
    uint32_t touchedHigh : 31 = 0;
    uint32_t touchedLow = 0;
    uint64_t touched() const { return uint64_t(touchedHigh) << 32 | touchedLow; }
    void setTouched(uint64_t stamp) {
      touchedHigh = uint32_t(stamp >> 32) & 0x7fffffffu;
      touchedLow = uint32_t(stamp);
    }
  };
  static_assert(sizeof(Cell) == 20);

  // Where a line cuts a cell, planned before anything changes. side: +1/-1 if the
  // cell lies wholly in front/behind (within eps), 0 if it straddles: then the cut
  // runs from `entry` (behind→front, walking the loop) to `exit` (front→behind).
  struct CutEnd {
    HalfEdgeId edge;     // loop half-edge: split it at `point`, or, if !split, its origin is the end
    bool split = false;
    Vec2 point{0.0};
  };
  struct CutPlan {
    CellId cell;
    int side = 0;
    CutEnd entry, exit;
  };
  struct CutResult {
    CellId front, back;
    HalfEdgeId chord;  // entry→exit, in the back cell
    std::vector<VertexId> newVertices;
  };

  // One cell: the receiver's convex CCW polygon (short edges dropped at eps).
  CellId reset(const Polygon2& receiver, double eps);

  CutPlan planCut(CellId cell, const Line2& line, double eps) const;
  // Applies a straddling plan: the front part keeps `plan.cell`, the back part is a
  // new cell; both hold the occluder list. New chord edges carry `node`.
  CutResult applyCut(const CutPlan& plan, NodeId node);

  // Removes the straight chain of edges shared by two adjacent cells (the inverse of
  // applyCut); `drop` dies, `keep` holds the union. Degree-2 vertices left on a
  // straight side between edges of the same node are dissolved. Returns removed vertices.
  std::vector<VertexId> mergeCells(CellId keep, CellId drop, double eps);

  Vertex vertex(VertexId v) const { return {positions_[v.index], outs_[v.index], outs_[v.index].is_valid()}; }
  const HalfEdge& halfEdge(HalfEdgeId h) const { return halfEdges_[h.index]; }
  // The tree node whose split created h's edge (both twins); invalid: receiver boundary.
  NodeId node(HalfEdgeId h) const { return edgeNodes_[h.index >> 1]; }
  const Cell& cell(CellId c) const { return cells_[c.index]; }
  // A cell's occluder list; valid until any cell's list changes or a cell dies.
  const OccluderList& occluders(CellId c) const { return lists_.list(cells_[c.index].occluders); }
  // Writers: a list write marks the cell touched; the leaf is bookkeeping only.
  void setOccluders(CellId c, const OccluderList& list);
  void setLeaf(CellId c, NodeId leaf) { cells_[c.index].leaf = leaf; }
  // The edge pair of h now belongs to `node` (a copy of its node, same line).
  void relabel(HalfEdgeId h, NodeId node) { edgeNodes_[h.index >> 1] = node; }
  // Marks a cell changed, so meshing looks at it again (see Cell::touched()).
  void touch(CellId c) { cells_[c.index].setTouched(nextStamp()); }
  // One clock shared by every mesh in the process, so a stamp read before meshing
  // is older than any later change of any tree, rebuilt trees included. Thread-safe.
  static uint64_t stampNow();
  static HalfEdgeId twin(HalfEdgeId h) { return HalfEdgeId(h.index ^ 1u); }
  VertexId destination(HalfEdgeId h) const { return halfEdge(twin(h)).origin; }

  // Slot counts (dead slots included) and live counts.
  size_t vertexSlots() const { return positions_.size(); }
  size_t halfEdgeSlots() const { return halfEdges_.size(); }
  size_t cellSlots() const { return cells_.size(); }
  size_t vertexCount() const { return liveVertices_; }
  size_t halfEdgeCount() const { return liveHalfEdges_; }
  size_t cellCount() const { return liveCells_; }
  size_t distinctOccluderLists() const { return lists_.distinctLists(); }

  std::vector<HalfEdgeId> loop(CellId c) const;
  void loopInto(CellId c, std::vector<HalfEdgeId>& out) const;  // the same, into `out` (cleared)
  Polygon2 polygon(CellId c) const;
  // Every live cell whose closure contains v, by a walk around v.
  std::vector<CellId> cellsAround(VertexId v) const;

  // Topology and geometry of the mesh alone (see DmTree::validate for the rest).
  void validate(double eps, double receiverArea) const;

  // Gives back the spare capacity of the slot arrays (grown by doubling while shadows
  // were inserted). Changes no slot, list or stamp.
  void shrinkToFit();

 private:
  static uint64_t nextStamp();
  // The half-edge before h in its loop, by a turn around h's origin: O(degree), not
  // O(loop) (the receiver's outside loop can have thousands of edges).
  HalfEdgeId prev(HalfEdgeId h) const;
  void kill(HalfEdgeId h) { halfEdges_[h.index].next = HalfEdgeId(); }
  VertexId addVertex(const Vec2& p);
  void killVertex(VertexId v);
  HalfEdgeId addEdgePair();  // counted live; alive() once the caller links its nexts
  VertexId splitEdge(HalfEdgeId h, const Vec2& p);
  void dissolveVertex(VertexId v);
  bool dissolvable(VertexId v, double eps) const;

  // By vertex: a live vertex's out half-edge is valid (set by its maker right after addVertex).
  std::vector<Vec2> positions_;
  std::vector<HalfEdgeId> outs_;
  std::vector<HalfEdge> halfEdges_;
  std::vector<NodeId> edgeNodes_;  // by edge pair (half-edge index / 2)
  std::vector<Cell> cells_;
  OccluderListPool lists_;  // the live cells' lists
  size_t liveVertices_ = 0, liveHalfEdges_ = 0, liveCells_ = 0;
};

}  // namespace penumbra
