// VisibleContour (the boundary of light minus shadows) against VisibleRegion's convex
// pieces: the same area and the same Lambert integral from random points above the
// light, with shadows sharing edges (a box's faces), duplicated, along the light's
// edges and holding the whole light; and exact cases whose answer is known.
#include "core/illum/visible_contour.h"

#include <gtest/gtest.h>

#include "tests/core/illum/random_convex.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "core/illum/lambert.h"
#include "core/illum/visible_region.h"

namespace penumbra {
namespace {

using penumbra::testing::randomConvex;

double perimeter(const Polygon2& polygon) {
  double sum = 0;
  for (size_t i = 0; i < polygon.size(); ++i) sum += glm::length(polygon[(i + 1) % polygon.size()] - polygon[i]);
  return sum;
}

Vec3 lifted(const Vec2& q) { return Vec3(q.x, q.y, 0.0); }

// Lambert's integral over the contour from p above the z = 0 plane (normal facing it).
double contourFactor(const VisibleContour& contour, const Vec3& p, const Vec3& n) {
  double sum = 0;
  for (const Segment2& s : contour.boundary()) sum += lambertEdgeTerm(p, n, lifted(s.from), lifted(s.to));
  return std::abs(0.5 * sum);
}

// The largest distance from an end point of the boundary that is left more or less
// often than it is reached to the nearest other such point: 0 when the boundary
// closes bit for bit; rounding where three edges meet leaves ~1e-16.
double widestGap(const VisibleContour& contour) {
  std::map<std::pair<double, double>, int> balance;
  for (const Segment2& s : contour.boundary()) {
    ++balance[{s.from.x, s.from.y}];
    --balance[{s.to.x, s.to.y}];
  }
  std::vector<Vec2> open;
  for (const auto& [point, count] : balance)
    if (count != 0) open.push_back({point.first, point.second});
  double widest = 0;
  for (const Vec2& p : open) {
    double nearest = open.size() > 1 ? INFINITY : 0;
    for (const Vec2& q : open)
      if (&p != &q) nearest = std::min(nearest, glm::length(p - q));
    widest = std::max(widest, nearest);
  }
  return widest;
}

bool sameBoundary(const VisibleContour& a, const VisibleContour& b) {
  if (a.boundary().size() != b.boundary().size()) return false;
  for (size_t i = 0; i < a.boundary().size(); ++i)
    if (a.boundary()[i].from != b.boundary()[i].from || a.boundary()[i].to != b.boundary()[i].to) return false;
  return true;
}

struct Flat {
  std::vector<Vec2> points;
  std::vector<uint32_t> starts{0};
  void add(const Polygon2& polygon) {
    points.insert(points.end(), polygon.begin(), polygon.end());
    starts.push_back(uint32_t(points.size()));
  }
};

// A shadow made to touch the previous one or the light in the ways faces do.
Polygon2 specialShadow(std::mt19937& rng, int kind, const Polygon2& light, const std::vector<Polygon2>& shadows) {
  std::uniform_real_distribution<double> unit(0, 1);
  const Polygon2& prev = shadows.empty() ? light : shadows.back();
  const size_t e = size_t(unit(rng) * prev.size()) % prev.size();
  const Vec2 a = prev[e], b = prev[(e + 1) % prev.size()];
  const Vec2 out = Vec2(b.y - a.y, a.x - b.x);  // right of a→b: outside prev
  switch (kind) {
    case 0: return {b, a, a + 0.7 * out, b + 0.4 * out};  // shares an edge, outside prev
    case 1: return prev;                                  // the same shadow again
    default: {                                            // along a light edge, inside it
      const Vec2 la = light[e % light.size()], lb = light[(e + 1) % light.size()];
      const Vec2 in = Vec2(la.y - lb.y, lb.x - la.x);
      return {la + 0.2 * (lb - la), la + 0.7 * (lb - la), la + 0.5 * (lb - la) + 0.3 * in};
    }
  }
}

TEST(VisibleContour, AgreesWithConvexPieces) {
  std::mt19937 rng(20261125);
  std::uniform_real_distribution<double> unit(0, 1);
  const double eps = 1e-10;
  size_t umbras = 0, partial = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const Polygon2 light = randomConvex(rng, 1.0);
    std::vector<Polygon2> shadows;
    const int count = 1 + trial % 40;
    for (int k = 0; k < count; ++k) {
      const bool special = k > 0 && k % 3 == 0;
      shadows.push_back(special ? specialShadow(rng, (k / 3) % 3, light, shadows)
                                : randomConvex(rng, trial % 3 == 0 ? 1.5 : 0.5));
    }
    Flat flat;
    VisibleRegion region;
    region.reset(light);
    double bound = eps * perimeter(light);
    bool anyCut = false;
    for (const Polygon2& shadow : shadows) {
      flat.add(shadow);
      anyCut |= region.subtract(shadow, eps);
      bound += eps * perimeter(shadow);
    }
    VisibleContour contour;
    contour.compute(light, flat.points, flat.starts, eps, true);
    VisibleContour unindexed;  // the twin index (sharedEdges) changes no bit of the boundary
    unindexed.compute(light, flat.points, flat.starts, eps);
    ASSERT_TRUE(sameBoundary(contour, unindexed)) << "trial " << trial;

    double pieces = 0;
    for (size_t i = 0; i < region.pieceCount(); ++i) pieces += signedArea(region.piece(i));
    ASSERT_NEAR(contour.area(), pieces, bound) << "trial " << trial;
    EXPECT_LE(widestGap(contour), 1e-14) << "trial " << trial;
    EXPECT_EQ(contour.occluded(), anyCut) << "trial " << trial;

    const Vec3 p{unit(rng) * 2 - 1, unit(rng) * 2 - 1, 0.05 + unit(rng)};
    const Vec3 n{0, 0, -1};  // all of the light's plane in front of p, as Backprojection clips it
    double expected = 0;
    for (size_t i = 0; i < region.pieceCount(); ++i) {
      Polygon3 piece;
      for (const Vec2& q : region.piece(i)) piece.push_back(lifted(q));
      expected += lambertIntegral(p, n, piece);
    }
    // A sliver of area ≤ bound seen from height ≥ 0.05 changes the factor by at most bound / h².
    EXPECT_NEAR(contourFactor(contour, p, n), expected, bound / (p.z * p.z)) << "trial " << trial;
    umbras += region.empty();
    partial += !region.empty() && anyCut;
  }
  std::printf("%zu umbras, %zu partly shadowed of 600\n", umbras, partial);
  EXPECT_GT(umbras, 20u);
  EXPECT_GT(partial, 200u);
}

// A tessellated patch as a mesh's faces project: triangles of a jittered grid over a rectangle,
// each interior edge shared exactly (reversed) by the two triangles beside it, given in a seeded
// shuffled order, with holes where cells are left out. What is left is the light less the cells
// kept, summed cell by cell (sharing nothing with the contour). Every shared edge is held whole
// by the triangle across it (the twin index, indexTwins) or, past the patch's edges, kept.
TEST(VisibleContour, TessellatedPatchLeavesTheLightLessItsCells) {
  const Polygon2 light{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  constexpr int kSide = 12;  // cells of 0.1 over [0.35, 1.55] x [-0.45, 0.75]
  size_t withHoles = 0;
  for (uint64_t seed = 1; seed <= 60; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> jitter(-0.03, 0.03), unit(0, 1);
    // Corners on the patch's border stay on it (only slide along it), so the cells tile the rectangle.
    std::vector<Vec2> corner((kSide + 1) * (kSide + 1));
    for (int y = 0; y <= kSide; ++y)
      for (int x = 0; x <= kSide; ++x) {
        const bool edgeX = x == 0 || x == kSide, edgeY = y == 0 || y == kSide;
        corner[size_t(y * (kSide + 1) + x)] = {0.35 + 0.1 * x + (edgeX ? 0.0 : jitter(rng)),
                                               -0.45 + 0.1 * y + (edgeY ? 0.0 : jitter(rng))};
      }
    const auto at = [&](int x, int y) { return corner[size_t(y * (kSide + 1) + x)]; };
    std::vector<Polygon2> triangles;
    std::vector<Polygon2> kept;  // the cells' triangles kept, for the expected area
    for (int y = 0; y < kSide; ++y)
      for (int x = 0; x < kSide; ++x) {
        if (seed % 2 == 0 && unit(rng) < 0.15) continue;  // a hole
        const Vec2 a = at(x, y), b = at(x + 1, y), c = at(x + 1, y + 1), d = at(x, y + 1);
        triangles.push_back({a, b, c});
        triangles.push_back({a, c, d});
      }
    withHoles += triangles.size() < size_t(2 * kSide * kSide);
    std::shuffle(triangles.begin(), triangles.end(), rng);
    Flat flat;
    VisibleRegion region;
    region.reset(light);
    for (const Polygon2& t : triangles) {
      flat.add(t);
      region.subtract(t, 1e-12);
    }
    VisibleContour contour;
    contour.compute(light, flat.points, flat.starts, 1e-12, true);
    VisibleContour unindexed;
    unindexed.compute(light, flat.points, flat.starts, 1e-12);
    ASSERT_TRUE(sameBoundary(contour, unindexed)) << "seed " << seed;
    // The light less each kept triangle's part inside it (they tile without overlap).
    double expected = 1.0;
    for (const Polygon2& t : triangles) {
      Polygon2 inside = t;
      for (size_t k = 0; k < light.size() && inside.size() >= 3; ++k) {
        inside = clipLeftOf(inside, light[k], light[(k + 1) % light.size()], 0.0);
      }
      if (inside.size() >= 3) expected -= signedArea(inside);
    }
    EXPECT_NEAR(contour.area(), expected, 1e-12) << "seed " << seed;
    EXPECT_LE(widestGap(contour), 1e-14) << "seed " << seed;
    double pieces = 0;
    for (size_t i = 0; i < region.pieceCount(); ++i) pieces += signedArea(region.piece(i));
    EXPECT_NEAR(contour.area(), pieces, 1e-10) << "seed " << seed;
    const Vec3 p{0.5, 0.5, 0.3}, n{0, 0, -1};
    double factor = 0;
    for (size_t i = 0; i < region.pieceCount(); ++i) {
      Polygon3 piece;
      for (const Vec2& q : region.piece(i)) piece.push_back(lifted(q));
      factor += lambertIntegral(p, n, piece);
    }
    EXPECT_NEAR(contourFactor(contour, p, n), factor, 1e-9) << "seed " << seed;
  }
  EXPECT_GT(withHoles, 25u);
}

TEST(VisibleContour, TwoHalvesSharingAnEdgeLeaveNothing) {
  const Polygon2 light{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  Flat flat;
  flat.add({{-1, -1}, {0.5, -1}, {0.5, 2}, {-1, 2}});
  flat.add({{0.5, -1}, {2, -1}, {2, 2}, {0.5, 2}});
  VisibleContour contour;
  contour.compute(light, flat.points, flat.starts, 1e-10);
  EXPECT_TRUE(contour.occluded());
  EXPECT_NEAR(contour.area(), 0.0, 1e-15);
  for (const Segment2& s : contour.boundary()) EXPECT_NEAR(glm::length(s.to - s.from), 0.0, 1e-15);
}

TEST(VisibleContour, ShadowAlongTheLightEdgeLeavesTheRest) {
  const Polygon2 light{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  Flat flat;
  flat.add({{0, 0}, {1, 0}, {1, 0.25}, {0, 0.25}});  // the bottom quarter, edges on the light's
  flat.add({{0, 0}, {1, 0}, {1, 0.25}, {0, 0.25}});  // twice
  flat.add({{0, -1}, {1, -1}, {1, 0}, {0, 0}});      // touching from outside
  VisibleContour contour;
  contour.compute(light, flat.points, flat.starts, 1e-10);
  EXPECT_TRUE(contour.occluded());
  EXPECT_DOUBLE_EQ(contour.area(), 0.75);
}

TEST(VisibleContour, TouchingFromOutsideRemovesNothing) {
  const Polygon2 light{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  Flat flat;
  flat.add({{0, -1}, {1, -1}, {1, 0}, {0, 0}});
  flat.add({{1, 0}, {2, 0}, {2, 1}, {1, 1}});
  VisibleContour contour;
  contour.compute(light, flat.points, flat.starts, 1e-10);
  EXPECT_FALSE(contour.occluded());
  EXPECT_DOUBLE_EQ(contour.area(), 1.0);
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

// A shadow whose corner sits 3e-11 from the light's corner (dense room N = 150, the
// floor): its edge is inside the light for less than eps, and dropping that stretch
// left the boundary open, 1.3e-9 relative off the value.
TEST(VisibleContour, ShadowCornerAtTheLightCornerKeepsTheBoundaryClosed) {
  const Polygon2 light{{0, 0}, {0, 1}, {-1, 1}, {-1, 0}};
  const Polygon2 clockwise{{-0.99999999999999956, 2.9869884343725062e-11},
                           {-0.58838828198590454, -0.024348224673862884},
                           {-0.61085639103682166, 0.063880802595908337},
                           {-1.0000575063683628, 0.092617357866731753}};
  const Polygon2 shadow = counterClockwise(clockwise);
  Flat flat;
  flat.add(shadow);
  const double eps = 1e-9;
  VisibleContour contour;
  contour.compute(counterClockwise(light), flat.points, flat.starts, eps);
  VisibleRegion region;
  region.reset(counterClockwise(light));
  region.subtract(shadow, eps);
  const Vec3 p{-0.7, 0.4, 0.8}, n{0, 0, -1};
  double expected = 0;
  for (size_t i = 0; i < region.pieceCount(); ++i) {
    Polygon3 piece;
    for (const Vec2& q : region.piece(i)) piece.push_back(lifted(q));
    expected += lambertIntegral(p, n, piece);
  }
  EXPECT_NEAR(contourFactor(contour, p, n), expected, 1e-13 * expected);
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

// Two faces that should share an edge but were snapped onto their planes apart (a
// cube vertex off by a micron): their shadows' edges cross at an angle of ~1e-7.
// Computed on each edge alone, the crossing points were 1e-10 apart and the open
// boundary put a grazing value 2e-7 relative off; computed alike, it closes.
TEST(VisibleContour, ShallowCrossingOfNearlySharedEdgesCloses) {
  const Polygon2 light{{0, 0}, {0, 1.5}, {-1.5, 1.5}, {-1.5, 0}};
  Flat flat;
  flat.add(counterClockwise({{-2.8730189452905481, 3.6213203435596402}, {-1.5000000000000071, 1.4999992678868486},
                             {0.28674076965139084, 0.76102939947884174}, {-0.77740933033437321, 3.6213203435596339}}));
  flat.add(counterClockwise({{0.28674058490911514, 0.7610289527931382}, {-1.4999998152579219, 1.4999997145726374},
                             {-2.2389695292652547, -0.28674321130451386}, {-0.45222839012924387, -1.0257121863428731}}));
  VisibleContour contour;
  contour.compute(counterClockwise(light), flat.points, flat.starts, 1e-9);
  EXPECT_TRUE(contour.occluded());
  EXPECT_EQ(widestGap(contour), 0.0);
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

// A star-shaped polygon around c, counter-clockwise: `corners` angles sorted with no gap
// of π or more (so its fan from c is of convex triangles), radii in [0.2, 1.1].
Polygon2 star(std::mt19937_64& rng, const Vec2& c, int corners) {
  std::uniform_real_distribution<double> unit(0, 1);
  Polygon2 out;
  for (int k = 0; k < corners; ++k) {
    const double a = (double(k) + 0.8 * unit(rng)) * 2 * M_PI / corners;
    out.push_back(c + (0.2 + 0.9 * unit(rng)) * Vec2(std::cos(a), std::sin(a)));
  }
  return out;
}

// subtractChain carries each stretch's winding along runs of chain edges joined end to start
// and walks it from the light's centre only at a run's first and last long stretch: on
// seeded stars (non-convex chains of up to 51 edges crossing one another and the light's
// edges) the boundary is the one every stretch walked gives, segment for segment, and its
// area is the light less the stars' fan triangles cut away as convex pieces.
TEST(VisibleContour, CarriedWindingsEqualWalkedOnes) {
  const Polygon2 light{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  const double eps = 1e-10;
  size_t long_runs = 0, partial = 0;
  for (uint64_t seed = 1; seed <= 300; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(-1, 1);
    std::vector<ChainEdge> chain;
    VisibleRegion region;
    region.reset(light);
    double bound = eps * 8;
    const int stars = 1 + int(seed % 3);
    for (int k = 0; k < stars; ++k) {
      const Vec2 c{unit(rng), unit(rng)};
      const Polygon2 polygon = star(rng, c, 12 + int(seed * 7 % 40));
      for (size_t i = 0; i < polygon.size(); ++i) {
        const Vec2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
        chain.push_back({a, b, 1});
        region.subtract(Polygon2{c, a, b}, eps);
        bound += eps * (glm::length(a - c) + glm::length(b - a) + glm::length(c - b));
      }
    }
    VisibleContour carried, walked;
    walked.setCarryWindings(false);
    for (VisibleContour* contour : {&carried, &walked}) {
      contour->compute(light, {}, {}, eps);
      contour->subtractChain(chain);
    }
    ASSERT_EQ(carried.boundary().size(), walked.boundary().size()) << "seed " << seed;
    for (size_t i = 0; i < carried.boundary().size(); ++i) {
      EXPECT_EQ(carried.boundary()[i].from, walked.boundary()[i].from) << "seed " << seed << " segment " << i;
      EXPECT_EQ(carried.boundary()[i].to, walked.boundary()[i].to) << "seed " << seed << " segment " << i;
    }
    double pieces = 0;
    for (size_t i = 0; i < region.pieceCount(); ++i) pieces += signedArea(region.piece(i));
    EXPECT_NEAR(carried.area(), pieces, bound) << "seed " << seed;
    long_runs += chain.size() > 30 ? 1 : 0;
    partial += pieces > 0.01 && pieces < 3.99 ? 1 : 0;
  }
  EXPECT_GT(long_runs, 100u);
  EXPECT_GT(partial, 100u);
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

// Rectangles on a grid of 1/8 as one chain (each rectangle's edges, counter-clockwise), turned
// by 0, 1e-9 or 0.3 rad: their edges run along each other, corners meet edges in a T, the
// light's centre lies on an edge or on an edge's line, exactly or to the last bits. The area left and its Lambert
// integral are summed over the grid's cells left, sharing nothing with the contour. (Edges along the light's own edges are
// another family, left out here: docs/BENCHMARKS.md.)
TEST(VisibleContour, RectangleChainsLeaveTheAreaTheGridCellsCount) {
  constexpr int kCells = 32;  // over [-2, 2]², the light [-1, 1]²
  const auto at = [](int k) { return -2.0 + double(k) / 8.0; };
  size_t along = 0;
  for (double angle : {0.0, 1e-9, 0.3}) {
    const double ca = std::cos(angle), sa = std::sin(angle);
    const auto turned = [&](int x, int y) { return Vec2(ca * at(x) - sa * at(y), sa * at(x) + ca * at(y)); };
    const Polygon2 light{turned(8, 8), turned(24, 8), turned(24, 24), turned(8, 24)};
    for (uint64_t seed = 1; seed <= 300; ++seed) {
      std::mt19937_64 rng(seed);
      std::uniform_int_distribution<int> corner(0, kCells), count(1, 6);
      const auto pick = [&] {
        const int k = corner(rng);
        return k == 8 || k == 24 ? k + 1 : k;  // not on the light's edges
      };
      std::vector<ChainEdge> chain;
      std::vector<uint8_t> covered(kCells * kCells, 0);
      const int rectangles = count(rng);
      for (int r = 0; r < rectangles; ++r) {
        int x0 = pick(), x1 = pick(), y0 = pick(), y1 = pick();
        if (x0 == x1 || y0 == y1) continue;
        if (x0 > x1) std::swap(x0, x1);
        if (y0 > y1) std::swap(y0, y1);
        const Vec2 a = turned(x0, y0), b = turned(x1, y0), c = turned(x1, y1), d = turned(x0, y1);
        chain.insert(chain.end(), {{a, b, 1}, {b, c, 1}, {c, d, 1}, {d, a, 1}});
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < x1; ++x) covered[size_t(y * kCells + x)] = 1;
      }
      if (chain.empty()) continue;
      mergeChainEdges(chain);
      // The cells left, their area and Lambert's integral from a point above the light.
      const Vec3 p{0.3 * std::cos(double(seed)), 0.3 * std::sin(double(seed)), 0.4}, n{0, 0, -1};
      double expected = 0, expectedFactor = 0;
      for (int y = 8; y < 24; ++y)
        for (int x = 8; x < 24; ++x) {
          if (covered[size_t(y * kCells + x)]) continue;
          expected += 1.0 / 64.0;
          const Polygon3 cell{lifted(turned(x, y)), lifted(turned(x + 1, y)), lifted(turned(x + 1, y + 1)),
                              lifted(turned(x, y + 1))};
          expectedFactor += lambertIntegral(p, n, cell);
        }
      VisibleContour contour;
      contour.compute(light, {}, {}, 1e-12);
      contour.subtractChain(chain);
      EXPECT_NEAR(contour.area(), expected, 1e-12) << "angle " << angle << " seed " << seed;
      EXPECT_NEAR(contourFactor(contour, p, n), expectedFactor, 1e-12) << "angle " << angle << " seed " << seed;
      along += rectangles > 1 ? 1 : 0;
    }
  }
  EXPECT_GT(along, 600u);
}

}  // namespace
}  // namespace penumbra
