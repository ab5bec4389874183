// Merging a closed convex object's shadows into their hull: the hull and group kernels
// by hand, and the visible factor with every face a candidate against the independent
// exact reference on dense rooms (boxes) and a 288-face sphere, at 1e-9 relative.
#include "core/illum/shadow_merge.h"

#include <gtest/gtest.h>

#include <random>

#include "core/illum/backprojection.h"
#include "core/reference/exact_irradiance.h"
#include "scenegen/dense_scene.h"
#include "scenegen/sphere_scene.h"

namespace penumbra {
namespace {

TEST(ShadowMerge, HullDropsInnerCollinearAndNearDuplicatePoints) {
  const std::vector<Vec2> points{{0, 0}, {1, 0}, {2, 0},         {2, 2},
                                 {1, 1}, {0, 2}, {2, 2 + 1e-17}, {0, 1}};
  std::vector<Vec2> hull;
  convexHullInto(points, 1e-9, hull);
  const std::vector<Vec2> expected{{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  EXPECT_EQ(hull, expected);
  convexHullInto(std::vector<Vec2>{{0, 0}, {1, 1}, {2, 2}}, 1e-9, hull);
  EXPECT_TRUE(hull.empty());  // no area
}

TEST(ShadowMerge, GroupsOfTwoOrMoreBecomeOneHullAtTheFirstPlace) {
  // Two unit squares side by side (group 7), a lone triangle, a lone square of group 9.
  const std::vector<Vec2> points{{0, 0}, {1, 0}, {1, 1}, {0, 1}, {5, 5}, {6, 5}, {5, 6}, {1, 0},
                                 {2, 0}, {2, 1}, {1, 1}, {8, 8}, {9, 8}, {9, 9}, {8, 9}};
  const std::vector<uint32_t> starts{0, 4, 7, 11, 15};
  const std::vector<uint32_t> groups{7, kNoGroup, 7, 9};
  std::vector<Vec2> outPoints;
  std::vector<uint32_t> outStarts;
  ASSERT_TRUE(mergeShadowGroups(points, starts, groups, 1e-9, outPoints, outStarts));
  const std::vector<uint32_t> expectedStarts{0, 4, 7, 11};
  EXPECT_EQ(outStarts, expectedStarts);
  EXPECT_EQ(outPoints[0], Vec2(0, 0));
  EXPECT_EQ(outPoints[1], Vec2(2, 0));
  EXPECT_EQ(outPoints[2], Vec2(2, 1));
  EXPECT_EQ(outPoints[3], Vec2(0, 1));
  const std::vector<uint32_t> alone{kNoGroup, kNoGroup, 3, 9};
  EXPECT_FALSE(mergeShadowGroups(points, starts, alone, 1e-9, outPoints, outStarts));
  EXPECT_EQ(outPoints, points);
}

// Every face a candidate at random floor points, against the reference.
void expectExactOnFloor(const Scene& scene, int points, uint64_t seed, double half) {
  const ExactReference reference(scene);
  std::vector<FaceId> all;
  for (const Face& face : scene.faces()) all.push_back(face.id);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-half, half);
  const Vec3 n(0, 1, 0);
  int penumbra = 0;
  for (int i = 0; i < points; ++i) {
    const Vec3 p(u(rng), 0, u(rng));
    const LightVisibleFactor mine = backproject(scene, 0, p, n, all);
    const LightVisibility truth = reference.visibility(p, n, 0);
    EXPECT_NEAR(mine.visibleFactor, truth.visibleFactor, 1e-9 * truth.unoccludedFactor)
        << "point " << i;
    penumbra += mine.lightClass == LightClass::Penumbra;
  }
  EXPECT_GT(penumbra, points / 10);  // the check is about partly hidden lights
}

TEST(ShadowMerge, DenseRoomsEveryFaceACandidateMatchReference) {
  for (uint64_t seed = 1; seed <= 3; ++seed)
    expectExactOnFloor(makeDenseScene({.boxes = 40, .seed = seed}), 300, seed, 2.9);
}

TEST(ShadowMerge, SphereMatchesReference) {
  expectExactOnFloor(makeSphereScene({.faces = 288}), 300, 5, 1.5);
}

}  // namespace
}  // namespace penumbra
