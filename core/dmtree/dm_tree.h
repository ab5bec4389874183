// The DM-tree of one receiving face (paper §2, §3.1): a 2D BSP tree whose leaves are
// the convex cells of a T-junction-free half-edge mesh, each with an occluder list.
// Changed only through insert/removeOccluder by its owner (the engine); not thread-safe.
#pragma once

#include <map>
#include <utility>
#include <vector>

#include "core/dmtree/half_edge_mesh.h"
#include "core/dmtree/single_tree.h"
#include "core/geom/tolerance.h"
#include "core/shadow/single_shadow.h"

namespace penumbra {

struct DmNode {
  Line2 line;  // internal nodes: front child is line.distance > 0
  NodeId front, back, parent;
  CellId cell;  // valid iff the node is a leaf
  // The generator of an internal node's line.
  uint32_t light = 0;
  FaceId occluder;
  SegmentKind kind = SegmentKind::Internal;
  ElementRef lightElement, occluderElement;
  Vec2 a{0.0}, b{0.0};   // the generating segment, clipped to the cell it split
  bool partial = false;  // the segment did not span that cell: construction edges extend it
  bool orphan = false;   // its occluder was removed but the node could not be condensed yet
  bool alive = true;
  bool isLeaf() const { return cell.is_valid(); }
};

struct InsertResult {
  std::vector<CellId> changedCells;   // cells whose occluder list gained the occluder
  std::vector<VertexId> newVertices;  // with changedCells' vertices: the relight set
  size_t nodesAdded = 0;              // internal (splitting) nodes added
};

struct RemoveResult {
  bool found = false;                     // the occluder had been inserted
  std::vector<CellId> changedCells;       // cells that lost the occluder (may have died in condensing)
  std::vector<VertexId> removedVertices;
  size_t nodesRemoved = 0;  // splitting nodes condensed away
  size_t nodesKept = 0;     // its nodes left as construction edges (orphans), see TODO below
};

class DmTree {
 public:
  // receiver: the face's convex CCW polygon in its 2D frame.
  DmTree(const Polygon2& receiver, const Tolerance& tolerance);

  // Builds the single tree of `shadow` and merges it in (paper §2.3). Throws
  // std::invalid_argument, before changing anything, if (light, occluder) is already in.
  InsertResult insert(const SingleShadow& shadow);

  // Removes every trace of one occluder: its occluder-list entries, and its nodes where
  // both children are leaves with equal lists (bottom-up condensing).
  // TODO(§3.1): a node of the occluder with a non-leaf subtree is kept as an orphan
  // construction edge; the paper's three-step deletion (unlink, extend dangling edges of
  // the cheaper subtree, E[cost_a] = D_a·size_b, insert the other) is not done yet.
  RemoveResult removeOccluder(uint32_t light, FaceId occluder);

  std::vector<CellId> cells() const;
  Polygon2 cellPolygon(CellId c) const { return mesh_.polygon(c); }
  const OccluderList& occluders(CellId c) const { return mesh_.cell(c).occluders; }
  std::vector<VertexId> vertices() const;
  Vec2 position(VertexId v) const { return mesh_.vertex(v).position; }
  // All cells whose closure contains v, by a half-edge walk around v.
  std::vector<CellId> cellsAround(VertexId v) const { return mesh_.cellsAround(v); }
  // The leaf cell containing p, by BSP descent (p on a line goes to the front).
  CellId locate(const Vec2& p) const;

  NodeId root() const { return root_; }
  const DmNode& node(NodeId n) const { return nodes_[n.index]; }
  const HalfEdgeMesh& mesh() const { return mesh_; }
  size_t nodeCount() const { return liveNodes_; }  // leaves included
  size_t internalNodeCount() const { return liveNodes_ - mesh_.cellCount(); }
  size_t cellCount() const { return mesh_.cellCount(); }
  size_t vertexCount() const { return mesh_.vertexCount(); }
  size_t halfEdgeCount() const { return mesh_.halfEdgeCount(); }
  double receiverArea() const { return receiverArea_; }

  // Throws std::logic_error on any broken invariant (mesh, BSP, occluder lists).
  void validate() const;

 private:
  using OccluderKey = std::pair<uint32_t, FaceId>;
  struct Generator {
    uint32_t light;
    FaceId occluder;
  };

  NodeId addNode(NodeId parent, CellId cell);
  void collectCells(NodeId n, const Polygon2& region, std::vector<CellId>& out) const;
  void partition(CellId c, const SingleTree& tree, int s, const Generator& gen, std::vector<CellId>& pieces,
                 InsertResult& result);
  void condense(NodeId n, const OccluderKey& key, RemoveResult& result);
  bool carriesLiveSegment(NodeId n) const;

  Tolerance tolerance_;
  double receiverArea_ = 0;
  HalfEdgeMesh mesh_;
  std::vector<DmNode> nodes_;
  size_t liveNodes_ = 0;
  NodeId root_;
  // The discontinuities each inserted occluder carries (kept so removal can tell
  // which edges other occluders still need).
  std::map<OccluderKey, std::vector<SingleTreeNode>> inserted_;
};

}  // namespace penumbra
