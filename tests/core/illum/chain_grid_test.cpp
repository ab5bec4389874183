// ChainGrid's promise: a query visits every indexed chain edge that meets the segment inside
// the grid's box. Checked by brute force on seeded random chains and segments, with eps 0 (no
// widening to hide a cell the walk skipped), and with segments through grid corners and along
// grid lines, where a walk must decide which way to step.
#include "core/illum/chain_grid.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

namespace penumbra {
namespace {

// Whether segments a→b and c→d share a point (closed segments; exact for the test's inputs
// up to rounding of the orientation products, which the test avoids by using dyadic points).
bool meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const auto orient = [](const Vec2& p, const Vec2& q, const Vec2& r) { return cross2(q - p, r - p); };
  const double d1 = orient(a, b, c), d2 = orient(a, b, d), d3 = orient(c, d, a), d4 = orient(c, d, b);
  const auto within = [](const Vec2& p, const Vec2& q, const Vec2& r) {
    return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
           r.y <= std::max(p.y, q.y);
  };
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  return (d1 == 0 && within(a, b, c)) || (d2 == 0 && within(a, b, d)) || (d3 == 0 && within(c, d, a)) ||
         (d4 == 0 && within(c, d, b));
}

// Every chain edge lies inside the grid's box, so an edge meeting a segment meets its part
// inside the box, the part the query walks.
TEST(ChainGrid, AQueryVisitsEveryEdgeThatMeetsItsSegment) {
  std::mt19937 random(35);
  // Points on a 1/64 lattice: cross products are exact, so `meet` is the truth.
  const auto coordinate = [&](double low, double high) {
    std::uniform_int_distribution<int> pick(int(low * 64), int(high * 64));
    return pick(random) / 64.0;
  };
  for (int trial = 0; trial < 300; ++trial) {
    const double side = 8;
    // count in [n², n² + 2n]: an n × n grid whose cells are 8 / n wide, so corners are known.
    const int n = 1 << std::uniform_int_distribution<int>(0, 4)(random);
    const size_t count = size_t(n * n) + std::uniform_int_distribution<size_t>(0, size_t(2 * n))(random);
    const double cellSide = side / n;
    const auto onCorner = [&](const Vec2& q) { return glm::round(q / cellSide) * cellSide; };
    std::vector<ChainEdge> chain;
    std::vector<uint32_t> indexed;
    for (size_t i = 0; i < count; ++i) {
      Vec2 from(coordinate(0, side), coordinate(0, side));
      if (i % 4 == 0) from = onCorner(from);  // edges from grid corners, where walks turn
      // Mostly short edges (a silhouette's), some across the box (visited by every query).
      const double reach = trial % 5 == 0 ? side : 1.5;
      const Vec2 to(std::clamp(from.x + coordinate(-reach, reach), 0.0, side),
                    std::clamp(from.y + coordinate(-reach, reach), 0.0, side));
      chain.push_back({from, to, 1});
      indexed.push_back(uint32_t(i));
    }
    ChainGrid grid;
    grid.build(chain, indexed, Vec2(0.0), Vec2(side), 0.0);
    for (int query = 0; query < 40; ++query) {
      Vec2 a(coordinate(-2, side + 2), coordinate(-2, side + 2)), b(coordinate(-2, side + 2), coordinate(-2, side + 2));
      if (query % 4 == 1) a = onCorner(a), b = a + Vec2(3.0, 3.0) * cellSide;   // through corners
      if (query % 4 == 2) a.y = b.y = onCorner(a).y;                            // along a grid line
      if (query % 4 == 3) a = onCorner(a), b = a + Vec2(-3.0, 3.0) * cellSide;  // the other diagonal
      std::set<uint32_t> visited;
      grid.forEachNear(a, b, [&](uint32_t j) { visited.insert(j); });
      for (uint32_t j : indexed) {
        if (!meet(a, b, chain[j].from, chain[j].to)) continue;
        EXPECT_TRUE(visited.count(j)) << "trial " << trial << " query " << query << ": edge " << j << " ("
                                        << chain[j].from.x << "," << chain[j].from.y << ")→(" << chain[j].to.x << ","
                                        << chain[j].to.y << ") meets (" << a.x << "," << a.y << ")→(" << b.x << ","
                                        << b.y << ") but was not visited";
      }
    }
  }
}

}  // namespace
}  // namespace penumbra
