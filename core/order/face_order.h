// Front-to-back order of the faces seen from one light (paper §2.1): a BSP tree T' of
// the front faces, offending faces filtered into its cells and sorted there by the
// graph method. Owned and edited by one writer (the engine); const access is thread-safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <vector>

#include "core/geom/plane.h"
#include "core/geom/polygon.h"
#include "core/geom/tolerance.h"
#include "core/order/offending_sort.h"
#include "core/scene/scene.h"

namespace penumbra {

// A node of T' (partitioning or leaf cell), an index into FaceOrder's node vector.
struct OrderNodeId {
  static constexpr uint32_t kInvalid = std::numeric_limits<uint32_t>::max();
  uint32_t value = kInvalid;
  bool isValid() const { return value != kInvalid; }
  bool operator==(const OrderNodeId&) const = default;
};

// A piece of a face. Splits are for ordering only: shadow code uses whole faces.
struct OrderedFragment {
  FaceId face;
  Polygon3 polygon;
};

struct FaceOrderCounters {
  size_t nodes = 0;                 // partitioning nodes of T'
  size_t cells = 0;                 // leaves of T'
  size_t fragments = 0;             // fragments in the walk (front + offending)
  size_t frontFaces = 0;
  size_t offendingFaces = 0;
  size_t offendingCellsSorted = 0;  // cells whose ≥ 2 offending fragments went through the graph sort
  size_t cycleSplits = 0;           // fragments split to open a cycle of the graph
  size_t cyclesBroken = 0;          // cycles that splitting could not open, broken by a fixed rule
};

class FaceOrder {
 public:
  // Orders the front and offending faces of `scene` for light `light`; back faces
  // are left out. Throws std::out_of_range if there is no such light, and
  // ResourceLimitError("tree_nodes") whenever the tree would pass `maxNodes` nodes
  // (here or in a later edit; the order is then unusable).
  FaceOrder(const Scene& scene, size_t light, size_t maxNodes = size_t(-1));

  // Front-to-back: a ray from any point of the light crosses (through their front
  // sides) fragments in increasing index order. The walk is rebuilt lazily: edits
  // only mark it stale, the first of these readers after an edit walks the tree.
  const std::vector<OrderedFragment>& fragments() const;
  // Each face once, at its first fragment.
  std::vector<FaceId> faceOrder() const;
  // Position of a face in faceOrder(); throws std::out_of_range if absent.
  size_t rank(FaceId face) const;
  // A face's place in the walk without walking the whole tree (what incremental
  // edits use): walkKey(a) < walkKey(b) (lexicographic) iff rank(a) < rank(b).
  // Costs O(fragments · depth). Throws std::out_of_range if absent.
  using WalkKey = std::vector<uint32_t>;
  WalkKey walkKey(FaceId face) const;
  bool contains(FaceId face) const { return faces_.count(face) != 0; }
  const FaceOrderCounters& counters() const;

  // Adds a face (world space, as in Scene::faces()). Back faces and faces already
  // present are ignored; returns whether the face was added.
  bool insertFace(const Face& face);
  // Removes a face; returns whether it was present. A partitioning node left with no
  // face on its plane is removed and its subtrees rebuilt from their fragments.
  bool removeFace(FaceId face);

  // Throws std::logic_error on a broken invariant (see face_order.cpp).
  void validate() const;

 private:
  using Fragment = PlanarFragment;
  struct Node {
    bool leaf = true;
    Plane plane;                        // partitioning plane (not for leaves)
    std::vector<Fragment> onPlane;      // fragments lying on `plane`
    std::vector<Fragment> offending;    // leaves: the cell's offending fragments, in order
    OrderNodeId front, back, parent;
    size_t cyclesBroken = 0;            // leaves: cycles broken in the last sort (validate skips order checks)
  };
  struct FaceRecord {
    Face face;
    FaceClass kind = FaceClass::Front;
    std::vector<OrderNodeId> nodes;  // nodes holding its fragments (with repeats)
  };

  OrderNodeId newNode(OrderNodeId parent);
  void freeNode(OrderNodeId id);
  // Builds a subtree at `at` (a fresh leaf) from front fragments, choosing planes.
  void buildSubtree(OrderNodeId at, std::vector<Fragment> front);
  // Filters an offending fragment down to cells; returns the cells it reached.
  void filterOffending(OrderNodeId from, Fragment fragment, std::vector<OrderNodeId>* cells);
  // Inserts a front fragment below `from`; a fragment reaching a leaf partitions it.
  void filterFront(OrderNodeId from, Fragment fragment);
  // Filters a fragment down from `from`, splitting it by node planes; pieces on a
  // node's plane stay there; each piece reaching a cell goes to atLeaf.
  void filterDown(OrderNodeId from, Fragment fragment, const std::function<void(OrderNodeId, Fragment)>& atLeaf);
  void sortCell(OrderNodeId cell);
  void collectSubtree(OrderNodeId id, std::vector<Fragment>* front,
                      std::vector<Fragment>* offending, std::vector<OrderNodeId>* nodes) const;
  // Marks the walk stale (edits) / rebuilds it if stale (readers; thread-safe).
  void invalidateWalk() { walkStale_ = true; }
  void ensureWalk() const;
  void rebuildWalk() const;
  void noteNode(const Fragment& fragment, OrderNodeId node);
  size_t chooseSplitter(const std::vector<Fragment>& candidates) const;

  Polygon3 light_;
  Tolerance tolerance_;
  size_t maxNodes_ = size_t(-1);
  std::vector<Node> nodes_;
  std::vector<OrderNodeId> freeNodes_;
  OrderNodeId root_;
  std::map<FaceId, FaceRecord> faces_;
  // The walk and what it derives, cached (mutable: rebuilt by const readers).
  mutable std::vector<OrderedFragment> walk_;
  mutable std::map<FaceId, size_t> rank_;
  mutable FaceOrderCounters counters_;
  mutable bool walkStale_ = true;
  mutable std::mutex walkMutex_;
};

}  // namespace penumbra
