// VisibleRegion (flat, buffer-reusing pieces) against convex2d's subtract: the same
// shadows in the same order give the same bit-identical pieces, also with shared
// edges (adjacent shadows) and after the region has emptied.
#include "core/illum/visible_region.h"

#include <gtest/gtest.h>

#include "tests/core/illum/random_convex.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace penumbra {
namespace {

using penumbra::testing::randomConvex;

// Pieces in a canonical order: the region keeps untouched pieces in place and
// appends remainders, so only the set is the fold's.
std::vector<Polygon2> sorted(std::vector<Polygon2> pieces) {
  std::sort(pieces.begin(), pieces.end(), [](const Polygon2& a, const Polygon2& b) {
    return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end(), [](const Vec2& p, const Vec2& q) {
      return p.x < q.x || (p.x == q.x && p.y < q.y);
    });
  });
  return pieces;
}

std::vector<Polygon2> piecesOf(const VisibleRegion& region) {
  std::vector<Polygon2> out;
  for (size_t i = 0; i < region.pieceCount(); ++i) out.emplace_back(region.piece(i).begin(), region.piece(i).end());
  return sorted(std::move(out));
}

TEST(VisibleRegion, EqualsFoldOfConvexSubtract) {
  std::mt19937 rng(20261123);
  const double eps = 1e-10;
  size_t emptied = 0, maxPieces = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Polygon2 light = randomConvex(rng, 1.0);
    std::vector<Polygon2> shadows;
    const int count = 1 + trial % 24;
    for (int k = 0; k < count; ++k) {
      shadows.push_back(randomConvex(rng, trial % 3 == 0 ? 1.5 : 0.5));
      // Every third shadow shares an edge with the previous one (a box's faces).
      if (k > 0 && k % 3 == 0) {
        const Polygon2& prev = shadows[k - 1];
        const Vec2 a = prev[0], b = prev[1];
        const Vec2 out = Vec2(b.y - a.y, a.x - b.x);  // right of a→b: outside prev
        shadows.back() = {b, a, a + 0.7 * out, b + 0.4 * out};
      }
    }
    VisibleRegion region;
    region.reset(light);
    std::vector<Polygon2> expected{light};
    for (const Polygon2& shadow : shadows) {
      bool anyCut = false;
      std::vector<Polygon2> next;
      for (const Polygon2& piece : expected) {
        bool cut = false;
        for (Polygon2& part : subtract(piece, shadow, eps, &cut)) next.push_back(std::move(part));
        anyCut |= cut;
      }
      expected = std::move(next);
      EXPECT_EQ(region.subtract(shadow, eps), anyCut) << "trial " << trial;
      ASSERT_EQ(piecesOf(region), sorted(expected)) << "trial " << trial;
      maxPieces = std::max(maxPieces, expected.size());
    }
    emptied += region.empty();
  }
  std::printf("%zu of 400 regions emptied, at most %zu pieces\n", emptied, maxPieces);
  EXPECT_GT(emptied, 0u);
  EXPECT_GT(maxPieces, 10u);
}

}  // namespace
}  // namespace penumbra
