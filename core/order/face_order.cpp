// Invariants checked by validate():
//  - the tree is well formed: children point back to their parent, leaves hold no
//    plane fragments, internal nodes hold no offending fragments, free nodes are unreachable;
//  - every plane fragment lies on its node's plane; every fragment lies in the
//    half-spaces of its cell (front of the planes whose front subtree holds it, back of the others);
//  - every recorded face is front or offending (never back), has fragments, and its
//    fragments' areas add up to its area; front faces never sit in cells;
//  - within a cell, no fragment may precede an earlier one (unless a cycle was broken there);
//  - the walk lists every fragment once and ranks are the faces' first positions.
#include "core/order/face_order.h"

#include <functional>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/geom/clip.h"
#include "core/geom/resource_limit.h"

namespace penumbra {

namespace {

// The rule of Scene::classify, for faces inserted after the build.
FaceClass classifyAgainst(const Plane& plane, const Polygon3& light, double eps) {
  bool anyFront = false, anyBack = false;
  for (const Vec3& p : light) {
    const double d = plane.signedDistance(p);
    anyFront |= d > eps;
    anyBack |= d < -eps;
  }
  if (anyFront && anyBack) return FaceClass::Offending;
  return anyFront ? FaceClass::Front : FaceClass::Back;
}

bool onPlane(const Polygon3& polygon, const Plane& plane, double eps) {
  return std::all_of(polygon.begin(), polygon.end(),
                     [&](const Vec3& p) { return std::abs(plane.signedDistance(p)) <= eps; });
}

// Splitter search: a few evenly spaced candidates, each scored on an evenly spaced
// sample of the set (fewest splits first, then balance).
constexpr size_t kSplitterCandidates = 8;
constexpr size_t kSplitterSample = 64;

[[noreturn]] void fail(const std::string& what) {
  throw std::logic_error("FaceOrder::validate: " + what);
}

}  // namespace

FaceOrder::FaceOrder(const Scene& scene, size_t light, size_t maxNodes) : maxNodes_(maxNodes) {
  light_ = scene.lights().at(light).polygon;
  tolerance_ = scene.tolerance();
  root_ = newNode(OrderNodeId{});
  const double eps = tolerance_.length();
  std::vector<Fragment> front, offending;
  for (const Face& face : scene.faces()) {
    if (face.area <= tolerance_.area()) continue;  // no plane: cannot order or shadow
    const FaceClass kind = classifyAgainst(face.plane, light_, eps);
    if (kind == FaceClass::Back) continue;
    faces_[face.id] = FaceRecord{face, kind, {}};
    (kind == FaceClass::Front ? front : offending)
        .push_back(Fragment{face.id, face.polygon, face.plane});
  }
  buildSubtree(root_, std::move(front));
  std::vector<OrderNodeId> cells;
  for (Fragment& f : offending) filterOffending(root_, std::move(f), &cells);
  std::sort(cells.begin(), cells.end(),
            [](OrderNodeId a, OrderNodeId b) { return a.value < b.value; });
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  for (OrderNodeId cell : cells) sortCell(cell);
  rebuildWalk();
  walkStale_ = false;
}

OrderNodeId FaceOrder::newNode(OrderNodeId parent) {
  OrderNodeId id;
  if (!freeNodes_.empty()) {
    id = freeNodes_.back();
    freeNodes_.pop_back();
    nodes_[id.value] = Node{};
  } else {
    if (nodes_.size() >= maxNodes_) throw ResourceLimitError("tree_nodes", nodes_.size() + 1, maxNodes_);
    id = OrderNodeId{static_cast<uint32_t>(nodes_.size())};
    nodes_.emplace_back();
  }
  nodes_[id.value].parent = parent;
  return id;
}

void FaceOrder::freeNode(OrderNodeId id) {
  nodes_[id.value] = Node{};
  freeNodes_.push_back(id);
}

void FaceOrder::noteNode(const Fragment& fragment, OrderNodeId node) {
  auto& nodes = faces_.at(fragment.face).nodes;
  if (nodes.empty() || !(nodes.back() == node)) nodes.push_back(node);
}

size_t FaceOrder::chooseSplitter(const std::vector<Fragment>& candidates) const {
  const size_t n = candidates.size();
  const size_t count = std::min(n, kSplitterCandidates);
  const size_t sample = std::min(n, kSplitterSample);
  const double eps = tolerance_.length();
  size_t best = 0, bestSplits = SIZE_MAX, bestImbalance = SIZE_MAX;
  for (size_t c = 0; c < count; ++c) {
    const size_t k = c * n / count;
    const Plane& plane = candidates[k].plane;
    size_t splits = 0, front = 0, back = 0;
    for (size_t s = 0; s < sample; ++s) {
      bool anyFront = false, anyBack = false;
      for (const Vec3& p : candidates[s * n / sample].polygon) {
        const double d = plane.signedDistance(p);
        anyFront |= d > eps;
        anyBack |= d < -eps;
      }
      splits += anyFront && anyBack;
      front += anyFront && !anyBack;
      back += anyBack && !anyFront;
    }
    const size_t imbalance = front > back ? front - back : back - front;
    if (splits < bestSplits || (splits == bestSplits && imbalance < bestImbalance)) {
      best = k;
      bestSplits = splits;
      bestImbalance = imbalance;
    }
  }
  return best;
}

void FaceOrder::buildSubtree(OrderNodeId at, std::vector<Fragment> front) {
  const double eps = tolerance_.length();
  struct Job {
    OrderNodeId at;
    std::vector<Fragment> fragments;
  };
  std::vector<Job> jobs;
  jobs.push_back({at, std::move(front)});
  while (!jobs.empty()) {
    Job job = std::move(jobs.back());
    jobs.pop_back();
    if (job.fragments.empty()) continue;
    const Fragment& splitter = job.fragments[chooseSplitter(job.fragments)];
    const Plane plane = splitter.plane;
    const FaceId splitterFace = splitter.face;
    std::vector<Fragment> inFront, behind;
    {
      Node& node = nodes_[job.at.value];
      node.leaf = false;
      node.plane = plane;
    }
    for (Fragment& f : job.fragments) {
      // The splitting face's own fragments stay on its plane whatever rounding says:
      // each node takes at least one face, so the tree cannot grow without end.
      Split3 split = f.face == splitterFace ? Split3{} : splitByPlane(f.polygon, plane, eps);
      if (split.front.empty() && split.back.empty()) {
        noteNode(f, job.at);
        nodes_[job.at.value].onPlane.push_back(std::move(f));
        continue;
      }
      if (!split.front.empty()) inFront.push_back({f.face, std::move(split.front), f.plane});
      if (!split.back.empty()) behind.push_back({f.face, std::move(split.back), f.plane});
    }
    const OrderNodeId frontChild = newNode(job.at);
    const OrderNodeId backChild = newNode(job.at);
    nodes_[job.at.value].front = frontChild;
    nodes_[job.at.value].back = backChild;
    jobs.push_back({backChild, std::move(behind)});
    jobs.push_back({frontChild, std::move(inFront)});
  }
}

void FaceOrder::filterOffending(OrderNodeId from, Fragment fragment,
                                std::vector<OrderNodeId>* cells) {
  filterDown(from, std::move(fragment), [&](OrderNodeId id, Fragment f) {
    noteNode(f, id);
    nodes_[id.value].offending.push_back(std::move(f));
    cells->push_back(id);
  });
}

void FaceOrder::filterFront(OrderNodeId from, Fragment fragment) {
  filterDown(from, std::move(fragment), [&](OrderNodeId id, Fragment f) {
    // The fragment partitions this cell; the cell's offending fragments follow it down.
    std::vector<Fragment> offending = std::move(nodes_[id.value].offending);
    nodes_[id.value].offending.clear();
    std::vector<Fragment> front{std::move(f)};
    buildSubtree(id, std::move(front));
    std::vector<OrderNodeId> cells;
    for (Fragment& o : offending) filterOffending(id, std::move(o), &cells);
    std::sort(cells.begin(), cells.end(), [](OrderNodeId a, OrderNodeId b) { return a.value < b.value; });
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    for (OrderNodeId cell : cells) sortCell(cell);
  });
}

void FaceOrder::filterDown(OrderNodeId from, Fragment fragment,
                           const std::function<void(OrderNodeId, Fragment)>& atLeaf) {
  const double eps = tolerance_.length();
  std::vector<std::pair<OrderNodeId, Fragment>> work;
  work.push_back({from, std::move(fragment)});
  while (!work.empty()) {
    auto [id, f] = std::move(work.back());
    work.pop_back();
    if (nodes_[id.value].leaf) {
      atLeaf(id, std::move(f));
      continue;
    }
    Split3 split = splitByPlane(f.polygon, nodes_[id.value].plane, eps);
    if (split.front.empty() && split.back.empty()) {
      // Only within tolerance of the light: a face on a front face's plane.
      noteNode(f, id);
      nodes_[id.value].onPlane.push_back(std::move(f));
      continue;
    }
    if (!split.back.empty())
      work.push_back({nodes_[id.value].back, Fragment{f.face, std::move(split.back), f.plane}});
    if (!split.front.empty())
      work.push_back({nodes_[id.value].front, Fragment{f.face, std::move(split.front), f.plane}});
  }
}

void FaceOrder::sortCell(OrderNodeId cell) {
  Node& node = nodes_[cell.value];
  node.cyclesBroken = 0;
  if (node.offending.size() < 2) return;
  OffendingOrder sorted = sortOffending(std::move(node.offending), light_, tolerance_);
  ++counters_.offendingCellsSorted;
  counters_.cycleSplits += sorted.splits;
  counters_.cyclesBroken += sorted.cyclesBroken;
  Node& after = nodes_[cell.value];
  after.cyclesBroken = sorted.cyclesBroken;
  after.offending = std::move(sorted.fragments);
  for (const Fragment& f : after.offending) noteNode(f, cell);
}

void FaceOrder::collectSubtree(OrderNodeId id, std::vector<Fragment>* front,
                               std::vector<Fragment>* offending,
                               std::vector<OrderNodeId>* nodes) const {
  std::vector<OrderNodeId> stack{id};
  while (!stack.empty()) {
    const OrderNodeId n = stack.back();
    stack.pop_back();
    nodes->push_back(n);
    const Node& node = nodes_[n.value];
    for (const Fragment& f : node.onPlane)
      (faces_.at(f.face).kind == FaceClass::Front ? front : offending)->push_back(f);
    for (const Fragment& f : node.offending) offending->push_back(f);
    if (!node.leaf) {
      stack.push_back(node.back);
      stack.push_back(node.front);
    }
  }
}

bool FaceOrder::insertFace(const Face& face) {
  if (faces_.count(face.id) || face.area <= tolerance_.area()) return false;
  const FaceClass kind = classifyAgainst(face.plane, light_, tolerance_.length());
  if (kind == FaceClass::Back) return false;
  faces_[face.id] = FaceRecord{face, kind, {}};
  Fragment fragment{face.id, face.polygon, face.plane};
  if (kind == FaceClass::Front) {
    filterFront(root_, std::move(fragment));
  } else {
    std::vector<OrderNodeId> cells;
    filterOffending(root_, std::move(fragment), &cells);
    std::sort(cells.begin(), cells.end(),
              [](OrderNodeId a, OrderNodeId b) { return a.value < b.value; });
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    for (OrderNodeId cell : cells) sortCell(cell);
  }
  invalidateWalk();
  return true;
}

bool FaceOrder::removeFace(FaceId faceId) {
  auto record = faces_.find(faceId);
  if (record == faces_.end()) return false;
  std::vector<OrderNodeId> holders = record->second.nodes;
  faces_.erase(record);
  std::sort(holders.begin(), holders.end(),
            [](OrderNodeId a, OrderNodeId b) { return a.value < b.value; });
  holders.erase(std::unique(holders.begin(), holders.end()), holders.end());
  // Drop its fragments. A cell's remaining order stays valid (a subsequence of a
  // topological order is one); a partitioning node left with no plane fragment goes.
  auto ofFace = [&](const Fragment& f) { return f.face == faceId; };
  std::vector<OrderNodeId> emptied;
  for (OrderNodeId id : holders) {
    Node& node = nodes_[id.value];
    std::erase_if(node.offending, ofFace);
    const size_t before = node.onPlane.size();
    std::erase_if(node.onPlane, ofFace);
    if (!node.leaf && before > 0 && node.onPlane.empty()) emptied.push_back(id);
  }
  // Rebuild only the topmost emptied nodes (Chrysanthou & Slater 1992: the subtrees'
  // fragments are re-inserted into the freed cell); ids are compared before any reuse.
  std::vector<OrderNodeId> topmost;
  for (OrderNodeId id : emptied) {
    bool covered = false;
    for (OrderNodeId up = nodes_[id.value].parent; up.isValid() && !covered;
         up = nodes_[up.value].parent)
      covered = std::find(emptied.begin(), emptied.end(), up) != emptied.end();
    if (!covered) topmost.push_back(id);
  }
  for (OrderNodeId id : topmost) {
    std::vector<Fragment> front, offending;
    std::vector<OrderNodeId> subtree;
    collectSubtree(id, &front, &offending, &subtree);
    for (OrderNodeId n : subtree)
      if (!(n == id)) freeNode(n);
    const OrderNodeId parent = nodes_[id.value].parent;
    nodes_[id.value] = Node{};
    nodes_[id.value].parent = parent;
    buildSubtree(id, std::move(front));
    std::vector<OrderNodeId> cells;
    for (Fragment& f : offending) filterOffending(id, std::move(f), &cells);
    std::sort(cells.begin(), cells.end(),
              [](OrderNodeId a, OrderNodeId b) { return a.value < b.value; });
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    for (OrderNodeId cell : cells) sortCell(cell);
  }
  invalidateWalk();
  return true;
}

void FaceOrder::ensureWalk() const {
  const std::lock_guard<std::mutex> lock(walkMutex_);
  if (!walkStale_) return;
  rebuildWalk();
  walkStale_ = false;
}

const std::vector<OrderedFragment>& FaceOrder::fragments() const {
  ensureWalk();
  return walk_;
}

const FaceOrderCounters& FaceOrder::counters() const {
  ensureWalk();
  return counters_;
}

FaceOrder::WalkKey FaceOrder::walkKey(FaceId face) const {
  const FaceRecord& record = faces_.at(face);
  // In-order walk: front subtree (0), the node's plane fragments (1), back subtree
  // (2); a cell lists its offending fragments in order. A fragment's key is its
  // root-to-node path of those digits, then its index there; the face's key is the
  // least over its fragments.
  WalkKey best;
  bool any = false;
  for (OrderNodeId id : record.nodes) {
    const Node& node = nodes_[id.value];
    const std::vector<Fragment>& list = node.leaf ? node.offending : node.onPlane;
    const auto it = std::find_if(list.begin(), list.end(), [&](const Fragment& f) { return f.face == face; });
    if (it == list.end()) continue;  // a stale holder (the face left that node)
    WalkKey key;
    key.push_back(uint32_t(it - list.begin()));
    if (!node.leaf) key.push_back(1);
    for (OrderNodeId child = id, up = node.parent; up.isValid(); child = up, up = nodes_[up.value].parent)
      key.push_back(nodes_[up.value].front == child ? 0 : 2);
    std::reverse(key.begin(), key.end());
    if (!any || key < best) best = std::move(key);
    any = true;
  }
  if (!any) throw std::out_of_range("FaceOrder::walkKey: face without fragments");
  return best;
}

void FaceOrder::rebuildWalk() const {
  walk_.clear();
  rank_.clear();
  counters_.nodes = counters_.cells = 0;
  std::vector<FaceId> order;
  // Light in front of every node plane: front subtree, the plane, back subtree.
  struct Visit {
    OrderNodeId id;
    bool expanded;
  };
  std::vector<Visit> stack{{root_, false}};
  auto emit = [&](const Fragment& f) {
    if (rank_.emplace(f.face, rank_.size()).second) order.push_back(f.face);
    walk_.push_back(OrderedFragment{f.face, f.polygon});
  };
  while (!stack.empty()) {
    const Visit visit = stack.back();
    stack.pop_back();
    const Node& node = nodes_[visit.id.value];
    if (node.leaf) {
      ++counters_.cells;
      for (const Fragment& f : node.offending) emit(f);
      continue;
    }
    if (!visit.expanded) {
      ++counters_.nodes;
      stack.push_back({node.back, false});
      stack.push_back({visit.id, true});
      stack.push_back({node.front, false});
      continue;
    }
    for (const Fragment& f : node.onPlane) emit(f);
  }
  counters_.fragments = walk_.size();
  counters_.frontFaces = counters_.offendingFaces = 0;
  for (const auto& [id, record] : faces_)
    ++(record.kind == FaceClass::Front ? counters_.frontFaces : counters_.offendingFaces);
}

std::vector<FaceId> FaceOrder::faceOrder() const {
  ensureWalk();
  std::vector<FaceId> order(rank_.size());
  for (const auto& [face, position] : rank_) order[position] = face;
  return order;
}

size_t FaceOrder::rank(FaceId face) const {
  ensureWalk();
  return rank_.at(face);
}

void FaceOrder::validate() const {
  ensureWalk();
  const double eps = tolerance_.length();
  if (!root_.isValid() || nodes_[root_.value].parent.isValid()) fail("bad root");
  std::map<FaceId, std::pair<size_t, double>> seen;  // fragments, area
  struct Step {
    Plane plane;
    bool front;
  };
  std::vector<Step> path;  // the half-spaces bounding the current node's cell
  size_t reachable = 0, fragmentCount = 0;
  struct Pending {
    OrderNodeId node;
    size_t depth;
    bool front;  // which side of its parent (unused for the root)
  };
  std::vector<Pending> stack{{root_, 0, true}};
  auto checkInCell = [&](const Polygon3& polygon) {
    for (const Step& step : path)
      for (const Vec3& p : polygon) {
        const double d = step.plane.signedDistance(p);
        if (step.front ? d < -eps : d > eps) fail("fragment outside its cell");
      }
  };
  auto account = [&](const Fragment& f) {
    auto record = faces_.find(f.face);
    if (record == faces_.end()) fail("fragment of an unknown face");
    if (f.polygon.size() < 3) fail("degenerate fragment");
    auto& s = seen[f.face];
    ++s.first;
    s.second += area(f.polygon);
    ++fragmentCount;
  };
  while (!stack.empty()) {
    const Pending pending = stack.back();
    stack.pop_back();
    const OrderNodeId id = pending.node;
    if (!id.isValid() || id.value >= nodes_.size()) fail("dangling node handle");
    if (++reachable > nodes_.size()) fail("the tree has a cycle");
    path.resize(pending.depth > 0 ? pending.depth - 1 : 0);
    if (pending.depth > 0) path.push_back({nodes_[nodes_[id.value].parent.value].plane, pending.front});
    const Node& node = nodes_[id.value];
    if (node.leaf) {
      if (!node.onPlane.empty()) fail("leaf with plane fragments");
      for (const Fragment& f : node.offending) {
        account(f);
        if (faces_.at(f.face).kind != FaceClass::Offending) fail("front face in a cell");
        checkInCell(f.polygon);
      }
      if (node.cyclesBroken == 0)
        for (size_t i = 0; i < node.offending.size(); ++i)
          for (size_t j = i + 1; j < node.offending.size(); ++j)
            if (mayPrecede(node.offending[j], node.offending[i], light_, tolerance_))
              fail("cell order contradicts the precedence graph");
      continue;
    }
    if (!node.offending.empty()) fail("partitioning node holds cell fragments");
    if (node.onPlane.empty()) fail("partitioning node without a face on its plane");
    if (classifyAgainst(node.plane, light_, eps) != FaceClass::Front)
      fail("partitioning plane does not face the light");
    for (const Fragment& f : node.onPlane) {
      account(f);
      if (!onPlane(f.polygon, node.plane, eps)) fail("plane fragment off its node's plane");
      checkInCell(f.polygon);
    }
    for (OrderNodeId child : {node.front, node.back})
      if (!child.isValid() || child.value >= nodes_.size() || !(nodes_[child.value].parent == id))
        fail("child does not point back to its parent");
    stack.push_back({node.back, pending.depth + 1, false});
    stack.push_back({node.front, pending.depth + 1, true});
  }
  if (fragmentCount != walk_.size()) fail("walk does not list every fragment once");
  for (const auto& [faceId, record] : faces_) {
    if (record.kind == FaceClass::Back) fail("back face recorded");
    if (classifyAgainst(record.face.plane, light_, eps) != record.kind) fail("face class changed");
    auto s = seen.find(faceId);
    if (s == seen.end()) fail("face without fragments");
    const double slack = eps * extent(record.face.polygon) * (s->second.first + 1);
    if (std::abs(s->second.second - record.face.area) > slack) fail("fragment areas do not add up");
  }
  if (rank_.size() != faces_.size()) fail("rank does not cover the faces");
  std::map<FaceId, size_t> firstSeen;
  for (const OrderedFragment& f : walk_) firstSeen.emplace(f.face, firstSeen.size());
  if (firstSeen != rank_) fail("ranks are not the faces' first positions in the walk");
  if (reachable + freeNodes_.size() != nodes_.size()) fail("lost or doubly used nodes");
}

}  // namespace penumbra
