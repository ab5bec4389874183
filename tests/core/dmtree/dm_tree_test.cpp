// DM-tree: seeded random shadows checked after every insert against brute-force
// oracles (lists by centroid, segment coverage, locate, cellsAround), targeted
// cases (boundary, snapping, full cover, identical shadows) and occluder removal.
#include "core/dmtree/dm_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <set>

namespace penumbra {
namespace {

using Rng = std::mt19937_64;
const Tolerance kTol = Tolerance::forSize(2.0);

double uniform(Rng& rng, double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }

Polygon2 randomConvex(Rng& rng, Vec2 center, double radius, int count) {
  std::vector<double> angles(count);
  for (double& a : angles) a = uniform(rng, 0, 2 * M_PI);
  std::sort(angles.begin(), angles.end());
  Polygon2 out;
  const double squash = uniform(rng, 0.5, 1.0);
  for (double a : angles) out.push_back(center + radius * Vec2{std::cos(a), squash * std::sin(a)});
  return out;
}

Polygon2 rect(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

bool inside(const Polygon2& poly, const Vec2& p) {
  if (poly.size() < 3) return false;
  for (size_t i = 0; i < poly.size(); ++i)
    if (!(lineDistance(poly[i], poly[(i + 1) % poly.size()], p) > 0)) return false;
  return true;
}

Vec2 centroidOf(const Polygon2& poly) {
  const Vec2 o = poly[0];
  Vec2 sum{0.0};
  double twice = 0;
  for (size_t i = 1; i + 1 < poly.size(); ++i) {
    const double w = cross2(poly[i] - o, poly[i + 1] - o);
    sum += w * (poly[i] + poly[i + 1] - 2.0 * o);
    twice += w;
  }
  return o + sum / (3.0 * twice);
}

// Where a ray from p (inside or on a convex CCW polygon) leaves it.
Vec2 rayExit(const Polygon2& poly, Vec2 p, Vec2 dir) {
  double best = INFINITY;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec2 a = poly[i], e = poly[(i + 1) % poly.size()] - a;
    const double den = cross2(dir, e);
    if (std::abs(den) < 1e-300) continue;
    const double t = cross2(a - p, e) / den, u = cross2(a - p, dir) / den;
    if (t > 1e-12 && u >= -1e-12 && u <= 1 + 1e-12) best = std::min(best, t);
  }
  return p + best * dir;
}

void addRegionSegments(SingleShadow& s, const Polygon2& poly, SegmentKind kind) {
  for (size_t i = 0; i < poly.size(); ++i) {
    CriticalSegment seg;
    seg.a = poly[i];
    seg.b = poly[(i + 1) % poly.size()];
    seg.kind = kind;
    seg.lightElement = {ElementRef::Kind::Vertex, uint16_t(i % 4)};
    seg.occluderElement = {ElementRef::Kind::Edge, uint16_t(i)};
    s.segments.push_back(seg);
  }
}

SingleShadow randomShadow(Rng& rng, const Polygon2& receiver, uint32_t id) {
  SingleShadow s;
  s.light = 0;
  s.occluder = FaceId{id, 0};
  for (;;) {
    const Vec2 c{uniform(rng, -1.1, 1.1), uniform(rng, -1.1, 1.1)};
    s.penumbra = intersect(randomConvex(rng, c, uniform(rng, 0.15, 0.8), 3 + int(rng() % 6)), receiver,
                           kTol.length());
    if (s.penumbra.size() >= 3 && signedArea(s.penumbra) > 1e-4) break;
  }
  const Vec2 pc = centroidOf(s.penumbra);
  if (rng() % 10 < 7) {
    Polygon2 u = randomConvex(rng, pc, uniform(rng, 0.05, 0.4), 3 + int(rng() % 5));
    s.umbra = intersect(u, s.penumbra, kTol.length());
    if (s.umbra.size() < 3 || signedArea(s.umbra) < 1e-5) s.umbra.clear();
  }
  addRegionSegments(s, s.penumbra, SegmentKind::Penumbra);
  addRegionSegments(s, s.umbra, SegmentKind::Umbra);
  const int internal = int(rng() % 4);
  for (int k = 0; k < internal; ++k) {
    CriticalSegment seg;
    seg.kind = SegmentKind::Internal;
    seg.lightElement = {ElementRef::Kind::Edge, uint16_t(k)};
    seg.occluderElement = {ElementRef::Kind::Vertex, uint16_t(k)};
    if (!s.umbra.empty()) {
      // EV-like: from the umbra boundary outwards to the penumbra boundary.
      const size_t i = rng() % s.umbra.size();
      const Vec2 a = s.umbra[i], b = s.umbra[(i + 1) % s.umbra.size()];
      const Vec2 p = a + uniform(rng, 0.1, 0.9) * (b - a);
      const Vec2 e = glm::normalize(b - a), n{e.y, -e.x};
      const double turn = uniform(rng, -0.7, 0.7);
      const Vec2 dir = std::cos(turn) * n + std::sin(turn) * e;
      seg.a = p;
      seg.b = rayExit(s.penumbra, p, dir);
    } else {
      const Vec2 p = pc + 0.5 * uniform(rng, 0, 1) * (s.penumbra[rng() % s.penumbra.size()] - pc);
      const double angle = uniform(rng, 0, 2 * M_PI);
      seg.a = p;
      seg.b = rayExit(s.penumbra, p, {std::cos(angle), std::sin(angle)});
    }
    if (std::isfinite(seg.b.x) && std::isfinite(seg.b.y) && glm::length(seg.b - seg.a) > 1e-6)
      s.segments.push_back(seg);
  }
  return s;
}

double pointSegmentDistance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 d = b - a;
  const double t = std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0);
  return glm::length(p - (a + t * d));
}

// Every shadow's discontinuities lie on mesh edges (sampled).
void expectCovered(const DmTree& tree, const SingleShadow& s) {
  const HalfEdgeMesh& mesh = tree.mesh();
  for (const CriticalSegment& seg : s.segments)
    for (int k = 0; k < 5; ++k) {
      const Vec2 p = seg.a + (k + 0.5) / 5.0 * (seg.b - seg.a);
      bool covered = false;
      for (uint32_t i = 0; i < mesh.halfEdgeSlots() && !covered; i += 2) {
        const HalfEdgeId h(i);
        if (!mesh.halfEdge(h).alive) continue;
        covered = pointSegmentDistance(p, mesh.vertex(mesh.halfEdge(h).origin).position,
                                       mesh.vertex(mesh.destination(h)).position) <= kTol.length();
      }
      ASSERT_TRUE(covered) << "segment point (" << p.x << ", " << p.y << ") not on any edge";
    }
}

// Lists by brute force: a shadow covers a cell iff its penumbra holds the centroid.
void expectLists(const DmTree& tree, const std::vector<SingleShadow>& shadows) {
  for (CellId c : tree.cells()) {
    const Vec2 p = centroidOf(tree.cellPolygon(c));
    std::set<std::pair<uint32_t, bool>> expected, actual;
    for (const SingleShadow& s : shadows)
      if (inside(s.penumbra, p)) expected.insert({s.occluder.object, inside(s.umbra, p)});
    for (const OccluderEntry& e : tree.occluders(c)) actual.insert({e.face.object, e.umbra});
    ASSERT_EQ(actual, expected) << "cell " << c.index;
  }
}

void expectQueries(const DmTree& tree) {
  const std::vector<CellId> cells = tree.cells();
  std::vector<Polygon2> polys;
  for (CellId c : cells) {
    polys.push_back(tree.cellPolygon(c));
    ASSERT_EQ(tree.locate(centroidOf(polys.back())), c);
  }
  for (VertexId v : tree.vertices()) {
    std::vector<CellId> around = tree.cellsAround(v);
    std::sort(around.begin(), around.end());
    std::vector<CellId> brute;
    for (size_t i = 0; i < cells.size(); ++i)
      if (contains(polys[i], tree.position(v), kTol.length())) brute.push_back(cells[i]);
    ASSERT_EQ(around, brute) << "vertex " << v.index;
  }
}

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
  EXPECT_EQ(tree.node(tree.node(tree.mesh().cell(mid).leaf).parent).kind, SegmentKind::Umbra);
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
  for (uint64_t seed = 1; seed <= 40; ++seed) {
    Rng rng(seed);
    const Polygon2 receiver = randomConvex(rng, {0, 0}, uniform(rng, 0.8, 1.2), 3 + int(rng() % 8));
    DmTree tree(receiver, kTol);
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
      expectLists(tree, shadows);
      expectCovered(tree, shadows.back());
      if (HasFatalFailure()) FAIL() << "seed " << seed << " insert " << k;
    }
    for (const SingleShadow& s : shadows) expectCovered(tree, s);
    expectQueries(tree);
    if (HasFatalFailure()) FAIL() << "seed " << seed;
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
  for (uint64_t seed = 200; seed < 225; ++seed) {
    Rng rng(seed);
    const Polygon2 receiver = randomConvex(rng, {0, 0}, 1.0, 3 + int(rng() % 8));
    DmTree tree(receiver, kTol);
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
      expectLists(tree, shadows);
      for (const SingleShadow& s : shadows) expectCovered(tree, s);
      if (HasFatalFailure()) FAIL() << "seed " << seed;
    }
    for (CellId c : tree.cells()) EXPECT_TRUE(tree.occluders(c).empty());
  }
}

}  // namespace
}  // namespace penumbra
