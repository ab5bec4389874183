// The cell root finder and the octant order on their own: known roots, the first of
// several, and the front-to-back walk covering the ray's span octant by octant. Seeded.
#include "core/volume/cell_hit.h"

#include <gtest/gtest.h>

#include <random>

#include "core/volume/octant_order.h"
#include "core/volume/volume_ray.h"

namespace penumbra {
namespace {

using namespace volume;

TEST(CellHit, LinearFieldRootIsExact) {
  CellCorners c{};  // f = x
  for (int i = 0; i < 8; ++i) c[i] = (i >> 2) & 1;
  const CellCubic cubic = cellCubic(c, {0.0, 0.5, 0.5}, {1.0, 0.0, 0.0}, 0.3);
  const auto t = firstRoot(cubic, 0.0, 1.0);
  ASSERT_TRUE(t);
  EXPECT_NEAR(*t, 0.3, 1e-14);
  EXPECT_FALSE(firstRoot(cubic, 0.0, 0.29));
  const Vec3 g = trilinearGradient(c, {0.3, 0.5, 0.5});
  EXPECT_NEAR(g.x, 1.0, 1e-15);
  EXPECT_NEAR(glm::length(g), 1.0, 1e-15);
}

TEST(CellHit, FindsTheFirstOfThreeRoots) {
  // (t − 0.2)(t − 0.5)(t − 0.8), and its mirror: a finder that stops at a later root fails.
  const CellCubic up{1.0, -1.5, 0.66, -0.08};
  const CellCubic down{-1.0, 1.5, -0.66, 0.08};
  for (const CellCubic& cubic : {up, down}) {
    const auto t = firstRoot(cubic, 0.0, 1.0);
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 0.2, 1e-12);
    const auto later = firstRoot(cubic, 0.3, 1.0);
    ASSERT_TRUE(later);
    EXPECT_NEAR(*later, 0.5, 1e-12);
  }
  // A double root pair inside one monotone-free span: (t − 0.4)(t − 0.45)·1 with no sign
  // change at the ends; the extremum split finds it.
  const CellCubic pair{0.0, 1.0, -0.85, 0.18};
  const auto t = firstRoot(pair, 0.0, 1.0);
  ASSERT_TRUE(t);
  EXPECT_NEAR(*t, 0.4, 1e-12);
}

TEST(OctantOrder, CoversTheSpanFrontToBackInsideEachOctant) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 3.0);
  for (int trial = 0; trial < 20000; ++trial) {
    const Vec3 origin(u(rng), u(rng), u(rng));
    Vec3 dir(u(rng) - 1.0, u(rng) - 1.0, u(rng) - 1.0);
    if (trial % 7 == 0) dir[trial % 3] = 0.0;  // axis-parallel rays too
    if (glm::length(dir) < 1e-3) continue;
    Vec3 inv;
    for (int a = 0; a < 3; ++a) inv[a] = dir[a] != 0.0 ? 1.0 / dir[a] : 0.0;
    const auto span = clipToBox({origin, dir}, Vec3(0.0), Vec3(2.0));  // cube [0, 2]³
    if (!span) continue;
    double last = span->t0;
    int visits = 0;
    walkOctants(origin, dir, inv, Vec3(1.0), span->t0, span->t1, [&](int c, double ta, double tb) {
      EXPECT_EQ(ta, last);  // contiguous, in order
      EXPECT_LE(ta, tb);
      last = tb;
      ++visits;
      const Vec3 mid = origin + dir * (0.5 * (ta + tb));
      const Vec3 lo((c >> 2) & 1, (c >> 1) & 1, c & 1);
      if (tb - ta > 1e-9)
        for (int a = 0; a < 3; ++a) {
          EXPECT_GE(mid[a], lo[a] - 1e-9) << trial;
          EXPECT_LE(mid[a], lo[a] + 1.0 + 1e-9) << trial;
        }
      return false;
    });
    EXPECT_EQ(last, span->t1);
    EXPECT_LE(visits, 4);
  }
}

}  // namespace
}  // namespace penumbra
