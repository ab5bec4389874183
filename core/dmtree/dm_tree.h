// The DM-tree of one receiving face (paper §2, §3.1): a 2D BSP tree whose leaves are
// the convex cells of a T-junction-free half-edge mesh, each with an occluder list.
// Changed only through insert/removeOccluder by its owner (the engine); not thread-safe.
#pragma once

#include <functional>
#include <map>
#include <utility>
#include <vector>

#include "core/dmtree/half_edge_mesh.h"
#include "core/dmtree/single_tree.h"
#include "core/geom/tolerance.h"
#include "core/shadow/single_shadow.h"

namespace penumbra {

// An internal node's line and what it came from: its generator (an index into its tree's
// table of (light, occluder) keys, DmTree::owner) and segment kind. Kept apart from the
// node, since half the nodes are leaves: 32 bytes, and 16 a node. Where the generator's
// segment lies on the line is in its kept segments (DmTree::forEachKeptSegment), not
// here: nothing in the tree reads it.
struct NodeSegment {
  Line2 line;           // front child is line.distance > 0
  uint32_t owner = 0;   // DmTree::owner()
  SegmentKind kind = SegmentKind::Internal;
  bool partial = false;  // the segment did not span that cell: construction edges extend it
  bool orphan = false;   // its occluder was removed but the node could not be condensed yet
  bool copy = false;     // made by splitting a node in two where an extended edge crossed it
};
static_assert(sizeof(NodeSegment) == 32);

// 16 bytes: a leaf keeps its cell's index where an internal node keeps its front child.
struct DmNode {
  static constexpr uint32_t kNoSegment = 0x3fffffffu;
  NodeId front, back;  // an internal node's children; a leaf's `front` holds its cell (cell())
  NodeId parent;
  // An internal node's NodeSegment (its line too); a leaf that was internal once keeps
  // its slot for reuse. 30 bits: the leaf and alive flags share the word.
  uint32_t segment : 30 = kNoSegment;
  bool leaf : 1 = false;
  bool alive : 1 = true;
  bool isLeaf() const { return leaf; }
  CellId cell() const { return leaf ? CellId(front.index) : CellId(); }  // invalid unless a leaf
  void makeLeaf(CellId c) {
    leaf = true;
    front = NodeId(c.index);
    back = NodeId();
  }
  void makeInternal(NodeId f, NodeId b) {
    leaf = false;
    front = f;
    back = b;
  }
};
static_assert(sizeof(DmNode) == 16);

struct InsertResult {
  std::vector<CellId> changedCells;   // cells whose occluder list gained the occluder
  std::vector<VertexId> newVertices;  // with changedCells' vertices: the relight set
  size_t nodesAdded = 0;              // internal (splitting) nodes added
};

struct RemoveResult {
  bool found = false;                     // the occluder had been inserted
  Polygon2 penumbra;                      // its penumbra as merged: outside it no value changed
  // Cells that lost the occluder or whose outline changed (re-split, extended or
  // merged); some may have died later in the same removal: check cell(c).alive.
  std::vector<CellId> changedCells;
  std::vector<VertexId> removedVertices;
  std::vector<VertexId> newVertices;      // made by extending or re-inserting edges
  size_t nodesRemoved = 0;    // the occluder's splitting nodes deleted (paper §3.1)
  size_t nodesRelabeled = 0;  // its nodes kept because a live occluder's segment lies on them
  size_t nodesKept = 0;       // its nodes left as orphan construction edges (0 unless a step failed)
  size_t nodesSplit = 0;      // nodes copied where an extended edge crossed them
  size_t copiesRemoved = 0;   // copies of its nodes (DmNode::copy) deleted
  size_t nodesCondensed = 0;  // splits of homogeneous cells removed afterwards
  // A geometric step failed and the tree was rebuilt from its stored shadows: every
  // earlier CellId/VertexId is invalid (the caller relights everything).
  bool rebuilt = false;
};

class DmTree {
 public:
  using OccluderKey = std::pair<uint32_t, FaceId>;  // (light, occluder face)

  // receiver: the face's convex CCW polygon in its 2D frame.
  DmTree(const Polygon2& receiver, const Tolerance& tolerance);

  // Builds the single tree of `shadow` and merges it in (paper §2.3). Throws
  // std::invalid_argument, before changing anything, if (light, occluder) is already in.
  // With umbra culling (on by default), a cell already in the umbra of the shadow's light
  // is neither split by its lines nor given its entry: the light is gone there whatever
  // else covers it (paper §2.4, why occluders come front to back). Only umbras that hide
  // the light at every point of their closure cull (SingleShadow::cullsBehind). The
  // shadow is still recorded, so removing the umbra can give the culled region back.
  // `beat` (may be empty) is called as a large shadow goes in (buildSingleTree's beats, then
  // every kCellsPerBeat cells it is merged into or splits it makes): a model's shadow on the
  // floor takes seconds.
  // It may throw to abandon the build: the tree is then only fit to be dropped.
  InsertResult insert(const SingleShadow& shadow, const std::function<void()>& beat = {});
  static constexpr size_t kCellsPerBeat = 64;
  void setUmbraCulling(bool on) { umbraCulling_ = on; }

  // Removes every trace of one occluder: its occluder-list entries (visiting only the
  // cells under its penumbra) and its nodes, top-down, then the copies splitting made
  // (paper §3.1). A node with two subtrees is deleted in three steps:
  // unlink its edge; take as basis the subtree a minimising E[cost_a] = (D_a + 1)·size_b
  // (D_a: dangling edges on a's side, size_b: live occluders' nodes in the other);
  // insert b into a: a's dangling edges extend across b's side, splitting only b's cells
  // they cross (b's other subtrees move whole, placed by their region's corners), and
  // each of a's leaves along the edge takes its share of b, b's dangling edges extending
  // across the leaf's cell; then condense extended splits of homogeneous cells. A node on
  // which a still-inserted occluder's segment lies is relabeled to it, not deleted. If
  // a geometric step fails (std::logic_error) the tree is rebuilt from the stored
  // shadows and `rebuilt` is set (a counted fallback, never the normal path).
  // Umbra culling: occluders of the same light inserted later and culled somewhere, whose
  // penumbra may reach into the removed umbra (and, transitively, into theirs), are
  // removed first, latest first, and inserted again afterwards in their order: the
  // freed region gets their lines and entries, and no deleted edge ever separates a
  // cell that lists one from a cell that culled it. Their cells and vertices are in
  // the result; values change only inside `penumbra`.
  RemoveResult removeOccluder(uint32_t light, FaceId occluder);
  // Occluders recorded but culled somewhere (umbra culling).
  size_t culledOccluders() const;
  // Calls f(light, occluder, segment) for every discontinuity segment of every inserted
  // occluder, as kept for removal (where umbra culling kept it out of the cells too).
  // They are derived from the stored shadows on each call.
  template <class F>
  void forEachKeptSegment(F&& f) const {
    for (const auto& [key, inserted] : inserted_)
      for (const KeptSegment& s : buildSingleTree(inserted.shadow, tolerance_).segments()) f(key.first, key.second, s);
  }

  std::vector<CellId> cells() const;
  Polygon2 cellPolygon(CellId c) const { return mesh_.polygon(c); }
  const OccluderList& occluders(CellId c) const { return mesh_.occluders(c); }
  std::vector<VertexId> vertices() const;
  Vec2 position(VertexId v) const { return mesh_.vertex(v).position; }
  // All cells whose closure contains v, by a half-edge walk around v.
  std::vector<CellId> cellsAround(VertexId v) const { return mesh_.cellsAround(v); }
  // Marks a cell changed for meshing (HalfEdgeMesh::Cell::touched): its owner calls
  // this when a value at one of its corners was recomputed.
  void touch(CellId c) { mesh_.touch(c); }
  // The leaf cell containing p, by BSP descent (p on a line goes to the front).
  CellId locate(const Vec2& p) const;

  NodeId root() const { return root_; }
  const DmNode& node(NodeId n) const { return nodes_[n.index]; }
  // An internal node's line, generator and segment.
  const NodeSegment& segment(NodeId n) const { return segments_[nodes_[n.index].segment]; }
  // The (light, occluder) whose segment an internal node's line carries.
  const OccluderKey& owner(NodeId n) const { return owners_[segment(n).owner]; }
  size_t ownerCount() const { return owners_.size(); }  // keys in the owner table
  const HalfEdgeMesh& mesh() const { return mesh_; }
  size_t nodeCount() const { return liveNodes_; }  // leaves included
  size_t nodeSlots() const { return nodes_.size(); }  // dead nodes included
  size_t segmentSlots() const { return segments_.size(); }  // unused ones included
  size_t internalNodeCount() const { return liveNodes_ - mesh_.cellCount(); }
  size_t cellCount() const { return mesh_.cellCount(); }
  size_t vertexCount() const { return mesh_.vertexCount(); }
  size_t halfEdgeCount() const { return mesh_.halfEdgeCount(); }
  double receiverArea() const { return receiverArea_; }

  // Throws std::logic_error on any broken invariant (mesh, BSP, occluder lists).
  void validate() const;

  // Gives back spare capacity (node slots, mesh arrays, occluder lists) once a batch of
  // insertions is done: the build's trees keep ~40 entries a cell in dense rooms.
  void shrinkToFit() {
    nodes_.shrink_to_fit();
    segments_.shrink_to_fit();
    mesh_.shrinkToFit();
  }

  // A cap on node slots: adding past it throws ResourceLimitError("tree_nodes"), so
  // one insertion or removal cannot run away (the tree is then unusable: drop it).
  void setNodeLimit(size_t maxNodeSlots) { nodeLimit_ = maxNodeSlots; }

 private:
  struct Generator {
    uint32_t light;
    FaceId occluder;
    const std::function<void()>* beat = nullptr;  // insert()'s, every kCellsPerBeat splits
  };

  NodeId addNode(NodeId parent, CellId cell);
  uint32_t addSegment(const NodeSegment& s);  // its slot
  NodeSegment& segmentForWrite(NodeId n) { return segments_[nodes_[n.index].segment]; }
  // key's index in owners_, added on first use.
  uint32_t ownerIndex(const OccluderKey& key);
  // Drops the keys no live node carries once they outnumber the live ones (removeOccluder).
  void compactOwners();
  // Splits leaf n's cell along `seg` (a straddling plan) and makes n the internal
  // node carrying seg's line for `owner`; partial: seg does not span the cell.
  HalfEdgeMesh::CutResult splitLeaf(NodeId n, const HalfEdgeMesh::CutPlan& plan, const SingleTreeNode& seg,
                                    const OccluderKey& owner, bool partial);
  // The cells below n overlapping `region`, in one descent with (if `nodes`) key's nodes there.
  void collectCells(NodeId n, const Polygon2& region, std::vector<CellId>& out, const OccluderKey* key = nullptr,
                    std::vector<NodeId>* nodes = nullptr) const;
  void partition(CellId c, const SingleTree& tree, int s, const Generator& gen, std::vector<CellId>& pieces,
                 InsertResult& result);
  void record(const OccluderKey& key, const SingleShadow& shadow);
  bool inUmbraOf(CellId c, uint32_t light) const;
  // The later culled occluders removing `key` must cast again, in insertion order.
  std::vector<OccluderKey> culledBehind(const OccluderKey& key) const;
  // removeOccluder without umbra culling's re-cast; adds to `result` (no final tidying).
  void removeOne(const OccluderKey& key, RemoveResult& result);

  // Node deletion (node_removal.cpp).
  Polygon2 regionOf(NodeId n) const;
  // Where n's line crosses n's region, as positions along the line: from the cells
  // below n when they are few (they tile the region), else from regionOf(n).
  bool chordOf(NodeId n, double& lo, double& hi) const;
  const KeptSegment* liveSegmentOn(NodeId n, double lo, double hi, const std::vector<OccluderKey>& keys,
                                   OccluderKey* owner);
  // An inserted occluder's discontinuity segments, derived from its shadow on first use
  // within one removeOccluder call (which clears them when it ends).
  const std::vector<KeptSegment>& keptSegments(const OccluderKey& key, const SingleShadow& shadow);
  void leavesAlong(NodeId n, const Vec2& p, const Vec2& q, std::vector<NodeId>& out) const;
  void deleteNode(NodeId e, const OccluderKey& key, RemoveResult& result);
  struct SplitTree {
    NodeId front, back;  // either invalid if nothing lies on that side
  };
  SplitTree partition(NodeId t, NodeId cutter, const Polygon2& region, RemoveResult& result);
  void mergeInto(NodeId n, NodeId t, const Polygon2& region, const Line2& deleted,
                 std::vector<NodeId>& extended, RemoveResult& result);
  void extendInto(NodeId n, CellId piece, const Line2& deleted, std::vector<NodeId>& extended,
                  RemoveResult& result);
  NodeId copyOf(NodeId n);
  void relabelEdges(NodeId from, NodeId to, NodeId under, const Polygon2& region);
  void condenseLeafPair(NodeId n, RemoveResult& result);
  void killNode(NodeId n);
  void rebuild();

  // Its discontinuity segments are not kept (10 MB in a sparse 1500 build, read only
  // when removing): keptSegments() derives them from the shadow.
  struct Inserted {
    SingleShadow shadow;                // its segments and penumbra, and the counted rebuild fallback
    uint64_t sequence = 0;              // insertion order
    bool culled = false;                // some cell it reaches was in its light's umbra
    // Its umbra culls later shadows (SingleShadow::cullsBehind).
    bool culls() const { return shadow.cullsBehind && !shadow.umbra.empty(); }
  };
  // Its penumbra as merged (short edges dropped), derived from the shadow: not kept.
  Polygon2 mergedPenumbra(const Inserted& inserted) const {
    return withoutShortEdges(inserted.shadow.penumbra, tolerance_.length());
  }

  Tolerance tolerance_;
  size_t nodeLimit_ = size_t(-1);
  bool umbraCulling_ = true;
  double receiverArea_ = 0;
  Polygon2 receiver_;
  HalfEdgeMesh mesh_;
  std::vector<DmNode> nodes_;
  std::vector<NodeSegment> segments_;  // by DmNode::segment
  std::vector<OccluderKey> owners_;    // by NodeSegment::owner
  std::map<OccluderKey, uint32_t> ownerIndex_;
  size_t liveNodes_ = 0;
  NodeId root_;
  // What each inserted occluder carries (kept so removal can tell which edges other
  // occluders still need, and re-insert them).
  std::map<OccluderKey, Inserted> inserted_;
  uint64_t nextSequence_ = 0;
  OccluderKey removing_{};  // the occluder removeOccluder is deleting (counts its nodes apart)
  // Nodes split in two (original and copy) by an extended edge, by generator: their
  // regions may miss the generator's penumbra. Dead or relabeled ones are skipped
  // when read (node slots are not reused).
  std::map<OccluderKey, std::vector<NodeId>> splitNodes_;
  std::map<OccluderKey, std::vector<KeptSegment>> keptSegments_;  // see keptSegments()
  OccluderList scratchList_;  // a list being changed before it is interned (its capacity reused)
};

}  // namespace penumbra
