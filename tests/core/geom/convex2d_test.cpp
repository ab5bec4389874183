// 2D convex polygon operations: known cases and seeded random properties
// (area conservation, disjoint pieces inside A, symmetric intersection).
#include "core/geom/convex2d.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace penumbra {
namespace {

constexpr double kConvexEps = 1e-9;  // like Tolerance::length() for a scene of size 1

Polygon2 rect(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

// A random convex CCW polygon: sorted angles on a circle, then a random affine
// map with positive determinant (keeps convexity and orientation).
Polygon2 randomConvex(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0, 1);
  const int count = 3 + int(unit(rng) * 6);
  std::vector<double> angles(count);
  for (double& a : angles) a = unit(rng) * 2 * M_PI;
  std::sort(angles.begin(), angles.end());
  const Vec2 center{unit(rng) * 2 - 1, unit(rng) * 2 - 1};
  const double sx = 0.1 + unit(rng), sy = 0.1 + unit(rng), rot = unit(rng) * 2 * M_PI;
  Polygon2 out;
  for (double a : angles) {
    const Vec2 q{sx * std::cos(a), sy * std::sin(a)};
    out.push_back(center + Vec2{std::cos(rot) * q.x - std::sin(rot) * q.y,
                                std::sin(rot) * q.x + std::cos(rot) * q.y});
  }
  return out;
}

bool isConvexCcw(const Polygon2& p) {
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec2 a = p[i], b = p[(i + 1) % p.size()], c = p[(i + 2) % p.size()];
    // Turning right by more than rounding (relative to the edge lengths) is a reflex corner.
    if (cross2(b - a, c - b) < -1e-12 * glm::length(b - a) * glm::length(c - b) - 1e-300)
      return false;
  }
  return signedArea(p) > 0;
}

double totalArea(const std::vector<Polygon2>& pieces) {
  double sum = 0;
  for (const Polygon2& p : pieces) sum += signedArea(p);
  return sum;
}

// Strictly inside by more than margin.
bool strictlyInside(const Polygon2& p, const Vec2& q, double margin) {
  for (size_t i = 0; i < p.size(); ++i)
    if (p[i] != p[(i + 1) % p.size()] && lineDistance(p[i], p[(i + 1) % p.size()], q) <= margin)
      return false;
  return p.size() >= 3;
}

TEST(Convex2d, SignedAreaAndOrientation) {
  const Polygon2 square = rect(0, 0, 2, 3);
  EXPECT_DOUBLE_EQ(signedArea(square), 6.0);
  Polygon2 reversed(square.rbegin(), square.rend());
  EXPECT_DOUBLE_EQ(signedArea(reversed), -6.0);
  EXPECT_DOUBLE_EQ(signedArea(counterClockwise(reversed)), 6.0);
  EXPECT_EQ(signedArea(Polygon2{{0, 0}, {1, 1}}), 0.0);
}

TEST(Convex2d, ClipByHalfPlane) {
  const Polygon2 square = rect(0, 0, 2, 2);
  // Keep the left of the upward line x = 0.5: the strip [0, 0.5] × [0, 2].
  EXPECT_NEAR(signedArea(clipLeftOf(square, {0.5, 0}, {0.5, 1}, kConvexEps)), 1.0, 1e-15);
  // Diagonal: half the square.
  EXPECT_NEAR(signedArea(clipLeftOf(square, {0, 0}, {2, 2}, kConvexEps)), 2.0, 1e-15);
  // Wholly left: unchanged; wholly right: empty.
  EXPECT_EQ(clipLeftOf(square, {3, 0}, {3, 1}, kConvexEps), square);
  EXPECT_TRUE(clipLeftOf(square, {-1, 0}, {-1, 1}, kConvexEps).empty());
  // Touching the line along an edge keeps nothing on the far side.
  EXPECT_TRUE(clipLeftOf(square, {2, 1}, {2, 0}, kConvexEps).empty());
  EXPECT_EQ(clipLeftOf(square, {2, 0}, {2, 1}, kConvexEps), square);
  // A vertex within eps beyond the line still counts as on it.
  const Polygon2 tri{{0, 0}, {1, 0}, {1, 1 + 0.5 * kConvexEps}};
  EXPECT_EQ(clipLeftOf(tri, {2, 1}, {0, 1}, kConvexEps), tri);
}

TEST(Convex2d, IntersectKnown) {
  const Polygon2 a = rect(0, 0, 2, 2), b = rect(1, 1, 3, 4);
  EXPECT_NEAR(signedArea(intersect(a, b, kConvexEps)), 1.0, 1e-15);
  EXPECT_TRUE(intersect(a, rect(2, 0, 3, 1), kConvexEps).empty());  // shares an edge only
  EXPECT_TRUE(intersect(a, rect(5, 5, 6, 6), kConvexEps).empty());
  EXPECT_NEAR(signedArea(intersect(a, rect(-1, -1, 3, 3), kConvexEps)), 4.0, 1e-15);
}

TEST(Convex2d, SubtractKnown) {
  const Polygon2 a = rect(0, 0, 3, 3);
  bool overlapped = false;
  // A hole in the middle: a frame of pieces, area 9 - 1.
  auto pieces = subtract(a, rect(1, 1, 2, 2), kConvexEps, &overlapped);
  EXPECT_TRUE(overlapped);
  EXPECT_EQ(pieces.size(), 4u);
  EXPECT_NEAR(totalArea(pieces), 8.0, 1e-14);
  // Disjoint or only touching: A comes back whole and unchanged.
  pieces = subtract(a, rect(3, 0, 4, 3), kConvexEps, &overlapped);
  EXPECT_FALSE(overlapped);
  ASSERT_EQ(pieces.size(), 1u);
  EXPECT_EQ(pieces[0], a);
  // Covered: nothing left.
  pieces = subtract(a, rect(-1, -1, 4, 4), kConvexEps, &overlapped);
  EXPECT_TRUE(overlapped);
  EXPECT_TRUE(pieces.empty());
  // Half: one piece of half the area.
  pieces = subtract(a, rect(1.5, -1, 4, 4), kConvexEps, &overlapped);
  EXPECT_TRUE(overlapped);
  EXPECT_NEAR(totalArea(pieces), 4.5, 1e-14);
  // Fold over a list: two overlapping bites.
  pieces = subtract(a, std::vector<Polygon2>{rect(0, 0, 2, 2), rect(1, 1, 3, 3)}, kConvexEps);
  EXPECT_NEAR(totalArea(pieces), 9.0 - 4 - 4 + 1, 1e-14);
}

TEST(Convex2d, ContainsIncludesBoundaryWithinEps) {
  const Polygon2 a = rect(0, 0, 1, 1);
  EXPECT_TRUE(contains(a, {0.5, 0.5}, kConvexEps));
  EXPECT_TRUE(contains(a, {1.0, 0.5}, kConvexEps));
  EXPECT_TRUE(contains(a, {1.0 + 0.5 * kConvexEps, 0.5}, kConvexEps));
  EXPECT_FALSE(contains(a, {1.0 + 2 * kConvexEps, 0.5}, kConvexEps));
  EXPECT_FALSE(contains(a, {-0.1, -0.1}, kConvexEps));
}

TEST(Convex2d, RandomIntersectionIsSymmetricAndInsideBoth) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-2, 2);
  int overlapping = 0;
  for (int k = 0; k < 600; ++k) {
    const Polygon2 a = randomConvex(rng), b = randomConvex(rng);
    const Polygon2 ab = intersect(a, b, kConvexEps), ba = intersect(b, a, kConvexEps);
    const double scale = std::max(signedArea(a), signedArea(b));
    EXPECT_NEAR(signedArea(ab), signedArea(ba), 1e-12 * scale) << "case " << k;
    if (ab.empty()) continue;
    ++overlapping;
    EXPECT_TRUE(isConvexCcw(ab)) << "case " << k;
    for (const Vec2& v : ab) {
      EXPECT_TRUE(contains(a, v, 2 * kConvexEps)) << "case " << k;
      EXPECT_TRUE(contains(b, v, 2 * kConvexEps)) << "case " << k;
    }
    for (int s = 0; s < 50; ++s) {
      const Vec2 q{coord(rng), coord(rng)};
      if (strictlyInside(a, q, 1e-7) && strictlyInside(b, q, 1e-7)) {
        EXPECT_TRUE(contains(ab, q, 0)) << "case " << k;
      }
    }
  }
  EXPECT_GT(overlapping, 100);  // the generator does exercise overlaps
}

TEST(Convex2d, RandomDifferenceConservesAreaAndTilesA) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coord(-2.2, 2.2);
  int cut = 0;
  for (int k = 0; k < 800; ++k) {
    const Polygon2 a = randomConvex(rng), b = randomConvex(rng);
    bool overlapped = false;
    const auto pieces = subtract(a, b, kConvexEps, &overlapped);
    const Polygon2 common = intersect(a, b, kConvexEps);
    const double areaA = signedArea(a);
    EXPECT_NEAR(areaA, signedArea(common) + totalArea(pieces), 1e-12 * areaA) << "case " << k;
    EXPECT_EQ(overlapped, !common.empty()) << "case " << k;
    EXPECT_LE(pieces.size(), b.size()) << "case " << k;
    cut += overlapped;
    for (const Polygon2& piece : pieces) {
      EXPECT_TRUE(isConvexCcw(piece)) << "case " << k;
      for (const Vec2& v : piece) EXPECT_TRUE(contains(a, v, 2 * kConvexEps)) << "case " << k;
    }
    // Sample points: each point well inside A is in exactly one of the pieces
    // and A ∩ B; points well outside A are in none; no piece reaches into B.
    for (int s = 0; s < 100; ++s) {
      const Vec2 q{coord(rng), coord(rng)};
      int inside = 0;
      for (const Polygon2& piece : pieces) inside += contains(piece, q, 0);
      const bool inCommon = !common.empty() && contains(common, q, 0);
      if (strictlyInside(a, q, 1e-7)) {
        const bool nearB = !strictlyInside(b, q, 1e-7) && contains(b, q, 1e-7);
        if (!nearB) {
          EXPECT_EQ(inside + int(inCommon), 1) << "case " << k;
        }
      }
      if (!contains(a, q, 1e-7)) {
        EXPECT_EQ(inside, 0) << "case " << k;
      }
      if (strictlyInside(b, q, 1e-7)) {
        EXPECT_EQ(inside, 0) << "case " << k;
      }
    }
  }
  EXPECT_GT(cut, 100);
}

TEST(Convex2d, RandomFoldOverTwoConservesArea) {
  // area(A \ (B1 ∪ B2)) = area(A) - area(A∩B1) - area(A∩B2) + area(A∩B1∩B2).
  std::mt19937 rng(23);
  for (int k = 0; k < 500; ++k) {
    const Polygon2 a = randomConvex(rng), b1 = randomConvex(rng), b2 = randomConvex(rng);
    const auto pieces = subtract(a, std::vector<Polygon2>{b1, b2}, kConvexEps);
    const Polygon2 a1 = intersect(a, b1, kConvexEps);
    const double expected = signedArea(a) - signedArea(a1) - signedArea(intersect(a, b2, kConvexEps)) +
                            signedArea(intersect(a1, b2, kConvexEps));
    EXPECT_NEAR(totalArea(pieces), expected, 1e-12 * signedArea(a))
        << "case " << k;
  }
}

}  // namespace
}  // namespace penumbra
