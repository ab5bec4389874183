// DM-tree: seeded random shadows checked after every insert against brute-force
// oracles (lists by centroid, segment coverage, locate, cellsAround), targeted
// cases (boundary, snapping, full cover, identical shadows) and occluder removal.
#include "core/dmtree/dm_tree.h"
#include "tests/core/dmtree/shadow_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <set>

namespace penumbra {
namespace {

using namespace dmtree_test;

TEST(DmTree, EmptyTreeIsTheReceiver) {
  DmTree tree(rect(0, 0, 2, 1), kTol);
  tree.validate();
  EXPECT_EQ(tree.cellCount(), 1u);
  EXPECT_EQ(tree.vertexCount(), 4u);
  EXPECT_EQ(tree.halfEdgeCount(), 8u);
  EXPECT_EQ(tree.nodeCount(), 1u);
  EXPECT_DOUBLE_EQ(tree.receiverArea(), 2.0);
}

TEST(DmTree, SquareShadowWithUmbra) {
  DmTree tree(rect(0, 0, 4, 4), kTol);
  SingleShadow s;
  s.occluder = {1, 0};
  s.penumbra = rect(1, 1, 3, 3);
  s.umbra = rect(1.5, 1.5, 2.5, 2.5);
  addRegionSegments(s, s.penumbra, SegmentKind::Penumbra);
  addRegionSegments(s, s.umbra, SegmentKind::Umbra);
  const InsertResult r = tree.insert(s);
  tree.validate();
  EXPECT_EQ(r.nodesAdded, 8u);
  const CellId mid = tree.locate({2, 2});
  ASSERT_EQ(tree.occluders(mid).size(), 1u);
  EXPECT_TRUE(tree.occluders(mid)[0].umbra);
  EXPECT_FALSE(tree.occluders(tree.locate({1.2, 2}))[0].umbra);
  EXPECT_TRUE(tree.occluders(tree.locate({0.5, 0.5})).empty());
  // Umbra cell keeps the generator of its last node.
  EXPECT_EQ(tree.segment(tree.node(tree.mesh().cell(mid).leaf).parent).kind, SegmentKind::Umbra);
  expectLists(tree, {s});
  expectCovered(tree, s);
  expectQueries(tree);
  EXPECT_THROW(tree.insert(s), std::invalid_argument);
}

TEST(DmTree, PartialNodeOnlySplitsCellsItsSegmentReaches) {
  // A cell that straddles the right edge's line but is crossed only by the top edge.
  DmTree tree(rect(-2, -2, 3, 3), kTol);
  SingleShadow first;
  first.occluder = {1, 0};
  first.penumbra = {{0.5, 0.99}, {2.9, 1.5}, {2.9, 1.6}};
  tree.insert(first);
  SingleShadow s;
  s.occluder = {2, 0};
  s.penumbra = rect(0, 0, 1, 1);
  addRegionSegments(s, s.penumbra, SegmentKind::Penumbra);
  tree.insert(s);
  tree.validate();
  expectLists(tree, {first, s});
  expectCovered(tree, s);
}

TEST(DmTree, ShadowTouchingReceiverBoundary) {
  DmTree tree(rect(0, 0, 2, 2), kTol);
  SingleShadow s;
  s.occluder = {1, 0};
  s.penumbra = rect(0, 0, 1, 2);  // three sides on the receiver's boundary
  s.umbra = rect(0, 0.5, 0.5, 1.5);
  addRegionSegments(s, s.penumbra, SegmentKind::Penumbra);
  addRegionSegments(s, s.umbra, SegmentKind::Umbra);
  const InsertResult r = tree.insert(s);
  tree.validate();
  EXPECT_EQ(r.nodesAdded, 4u);  // x=1, then the umbra's three inner sides
  expectLists(tree, {s});
  expectCovered(tree, s);
  expectQueries(tree);
}

TEST(DmTree, CoincidentCornersShareOneVertex) {
  DmTree tree(rect(0, 0, 4, 4), kTol);
  SingleShadow a, b;
  a.occluder = {1, 0};
  a.penumbra = rect(1, 1, 2, 2);
  b.occluder = {2, 0};
  const double off = 0.3 * kTol.length();  // within the snapping distance
  b.penumbra = {{2 + off, 2 - off}, {3, 2.5}, {2.5, 3}};
  addRegionSegments(a, a.penumbra, SegmentKind::Penumbra);
  addRegionSegments(b, b.penumbra, SegmentKind::Penumbra);
  tree.insert(a);
  const size_t before = tree.vertexCount();
  const InsertResult r = tree.insert(b);
  tree.validate();
  int near = 0;
  for (VertexId v : tree.vertices()) near += glm::length(tree.position(v) - Vec2{2, 2}) < 10 * kTol.length();
  EXPECT_EQ(near, 1);
  EXPECT_EQ(tree.vertexCount(), before + r.newVertices.size());
  // The shared corner has cells from both shadows around it.
  for (VertexId v : tree.vertices())
    if (glm::length(tree.position(v) - Vec2{2, 2}) < 10 * kTol.length()) {
      std::set<uint32_t> seen;
      for (CellId c : tree.cellsAround(v))
        for (const OccluderEntry& e : tree.occluders(c)) seen.insert(e.face.object);
      EXPECT_EQ(seen, (std::set<uint32_t>{1, 2}));
    }
  expectQueries(tree);
}

TEST(DmTree, WholeReceiverInUmbraAddsNoEdges) {
  const Polygon2 receiver = {{0, 0}, {2, 0}, {2.5, 1}, {1, 2}};
  DmTree tree(receiver, kTol);
  SingleShadow part;
  part.occluder = {1, 0};
  part.penumbra = rect(0.5, 0.2, 1.5, 1.0);
  addRegionSegments(part, part.penumbra, SegmentKind::Penumbra);
  tree.insert(part);
  const size_t cells = tree.cellCount(), edges = tree.halfEdgeCount(), vertices = tree.vertexCount();
  SingleShadow all;
  all.occluder = {2, 0};
  all.penumbra = receiver;
  all.umbra = receiver;
  addRegionSegments(all, all.penumbra, SegmentKind::Penumbra);
  addRegionSegments(all, all.umbra, SegmentKind::Umbra);
  const InsertResult r = tree.insert(all);
  tree.validate();
  EXPECT_EQ(r.nodesAdded, 0u);
  EXPECT_TRUE(r.newVertices.empty());
  EXPECT_EQ(r.changedCells.size(), cells);
  EXPECT_EQ(tree.cellCount(), cells);
  EXPECT_EQ(tree.halfEdgeCount(), edges);
  EXPECT_EQ(tree.vertexCount(), vertices);
  for (CellId c : tree.cells()) {
    ASSERT_FALSE(tree.occluders(c).empty());
    EXPECT_EQ(tree.occluders(c)[0], (OccluderEntry{0, {2, 0}, true}));  // umbra at the head
  }
  expectLists(tree, {part, all});
}

TEST(DmTree, IdenticalShadowsFromTwoOccluders) {
  Rng rng(7);
  const Polygon2 receiver = randomConvex(rng, {0, 0}, 1.0, 7);
  DmTree tree(receiver, kTol);
  SingleShadow a = randomShadow(rng, receiver, 1);
  SingleShadow b = a;
  b.occluder = {2, 0};
  tree.insert(a);
  const size_t cells = tree.cellCount(), vertices = tree.vertexCount();
  const InsertResult r = tree.insert(b);
  tree.validate();
  EXPECT_EQ(r.nodesAdded, 0u);
  EXPECT_EQ(tree.cellCount(), cells);
  EXPECT_EQ(tree.vertexCount(), vertices);
  expectLists(tree, {a, b});
  // Removing one keeps every edge the other needs.
  tree.removeOccluder(0, a.occluder);
  tree.validate();
  expectLists(tree, {b});
  expectCovered(tree, b);
  EXPECT_EQ(tree.cellCount(), cells);
}

struct Snapshot {
  std::vector<std::pair<std::vector<std::pair<double, double>>, OccluderList>> cells;
  size_t vertices, halfEdges, nodes;
  bool operator==(const Snapshot&) const = default;
};

Snapshot snapshot(const DmTree& tree) {
  Snapshot s;
  for (CellId c : tree.cells()) {
    std::vector<std::pair<double, double>> pts;
    for (const Vec2& p : tree.cellPolygon(c)) pts.push_back({p.x, p.y});
    std::sort(pts.begin(), pts.end());
    s.cells.push_back({pts, tree.occluders(c)});
  }
  std::sort(s.cells.begin(), s.cells.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  s.vertices = tree.vertexCount();
  s.halfEdges = tree.halfEdgeCount();
  s.nodes = tree.nodeCount();
  return s;
}

TEST(DmTree, RandomInsertsKeepEveryInvariant) {
  double insertSeconds = 0;
  size_t inserts = 0;
  for (bool culling : {false, true})
  for (uint64_t seed = 1; seed <= 40; ++seed) {
    Rng rng(seed);
    const Polygon2 receiver = randomConvex(rng, {0, 0}, uniform(rng, 0.8, 1.2), 3 + int(rng() % 8));
    DmTree tree(receiver, kTol);
    tree.setUmbraCulling(culling);
    const int count = 1 + int(rng() % 30);
    std::vector<SingleShadow> shadows;
    for (int k = 0; k < count; ++k) {
      shadows.push_back(randomShadow(rng, receiver, uint32_t(k + 1)));
      const auto start = std::chrono::steady_clock::now();
      const InsertResult r = tree.insert(shadows.back());
      insertSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      ++inserts;
      ASSERT_NO_THROW(tree.validate()) << "seed " << seed << " insert " << k;
      for (CellId c : r.changedCells) ASSERT_TRUE(tree.mesh().cell(c).alive);
      expectLists(tree, shadows, culling);
      expectCovered(tree, shadows.back(), culling);
      if (HasFatalFailure()) FAIL() << "culling " << culling << " seed " << seed << " insert " << k;
    }
    for (const SingleShadow& s : shadows) expectCovered(tree, s, culling);
    expectQueries(tree);
    if (HasFatalFailure()) FAIL() << "culling " << culling << " seed " << seed;
    if (count == 30 || seed == 40)
      std::printf("seed %llu: %d shadows -> %zu nodes (%zu internal), %zu cells, %zu vertices, %zu half-edges\n",
                  (unsigned long long)seed, count, tree.nodeCount(), tree.internalNodeCount(), tree.cellCount(),
                  tree.vertexCount(), tree.halfEdgeCount());
  }
  std::printf("mean insert: %.1f us over %zu inserts\n", 1e6 * insertSeconds / inserts, inserts);
}

TEST(DmTree, RemoveLastInsertedRestoresTheTree) {
  for (uint64_t seed = 100; seed < 130; ++seed) {
    Rng rng(seed);
    const Polygon2 receiver = randomConvex(rng, {0, 0}, 1.0, 3 + int(rng() % 8));
    DmTree tree(receiver, kTol);
    std::vector<SingleShadow> shadows;
    const int count = int(rng() % 12);
    for (int k = 0; k < count; ++k) {
      shadows.push_back(randomShadow(rng, receiver, uint32_t(k + 1)));
      tree.insert(shadows.back());
    }
    const Snapshot before = snapshot(tree);
    const SingleShadow extra = randomShadow(rng, receiver, 999);
    tree.insert(extra);
    const RemoveResult r = tree.removeOccluder(0, extra.occluder);
    ASSERT_TRUE(r.found);
    ASSERT_NO_THROW(tree.validate()) << "seed " << seed;
    EXPECT_EQ(r.nodesKept, 0u) << "seed " << seed;
    EXPECT_TRUE(snapshot(tree) == before) << "seed " << seed;
    EXPECT_FALSE(tree.removeOccluder(0, extra.occluder).found);
  }
}

TEST(DmTree, RemoveAnyOccluderKeepsListsAndEdges) {
  for (bool culling : {false, true})
  for (uint64_t seed = 200; seed < 225; ++seed) {
    Rng rng(seed);
    const Polygon2 receiver = randomConvex(rng, {0, 0}, 1.0, 3 + int(rng() % 8));
    DmTree tree(receiver, kTol);
    tree.setUmbraCulling(culling);
    std::vector<SingleShadow> shadows;
    const int count = 2 + int(rng() % 15);
    for (int k = 0; k < count; ++k) {
      shadows.push_back(randomShadow(rng, receiver, uint32_t(k + 1)));
      tree.insert(shadows.back());
    }
    // Remove in a random order, checking after each, until none is left.
    std::shuffle(shadows.begin(), shadows.end(), rng);
    while (!shadows.empty()) {
      const SingleShadow gone = shadows.back();
      shadows.pop_back();
      ASSERT_TRUE(tree.removeOccluder(gone.light, gone.occluder).found);
      ASSERT_NO_THROW(tree.validate()) << "seed " << seed;
      expectLists(tree, shadows, culling);
      for (const SingleShadow& s : shadows) expectCovered(tree, s, culling);
      if (HasFatalFailure()) FAIL() << "culling " << culling << " seed " << seed;
    }
    for (CellId c : tree.cells()) EXPECT_TRUE(tree.occluders(c).empty());
    EXPECT_EQ(tree.culledOccluders(), 0u);
  }
}

}  // namespace
}  // namespace penumbra
