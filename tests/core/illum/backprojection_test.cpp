// Lambert's formula against closed forms, and Backprojection on hand-built scenes:
// the single-sided rule, the cone, comparisons counted, classes.
#include "core/illum/backprojection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/illum/lambert.h"
#include "core/reference/exact_irradiance.h"

namespace penumbra {
namespace {

// π × the form factor from a point below a corner of an a×b rectangle at height h.
double cornerFactor(double a, double b, double h) {
  const double x = a / h, y = b / h;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return 0.5 * (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy));
}

TEST(Lambert, CornerRectangleClosedForm) {
  for (double h : {0.3, 1.0, 4.0}) {
    const Polygon3 rect{{0, h, 0}, {2, h, 0}, {2, h, 1.5}, {0, h, 1.5}};
    const double expected = cornerFactor(2, 1.5, h);
    EXPECT_NEAR(lambertIntegral(Vec3(0.0), Vec3(0, 1, 0), rect), expected, 1e-14);
    // Winding does not matter.
    const Polygon3 reversed(rect.rbegin(), rect.rend());
    EXPECT_NEAR(lambertIntegral(Vec3(0.0), Vec3(0, 1, 0), reversed), expected, 1e-14);
  }
}

TEST(Lambert, HemisphereLimitIsPi) {
  const double s = 1e6;
  const Polygon3 huge{{-s, 1, -s}, {s, 1, -s}, {s, 1, s}, {-s, 1, s}};
  EXPECT_NEAR(lambertIntegral(Vec3(0.0), Vec3(0, 1, 0), huge), M_PI, 1e-5);
}

TEST(Lambert, AgreesWithReferenceOnRandomTriangles) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 200; ++i) {
    const Vec3 n = glm::normalize(Vec3(u(rng), u(rng), u(rng)));
    Polygon3 tri;
    for (int k = 0; k < 3; ++k) {
      Vec3 v(u(rng), u(rng), u(rng));
      if (glm::dot(v, n) < 0.05) v += (0.05 - glm::dot(v, n)) * n;  // in front of p
      tri.push_back(v);
    }
    const double mine = lambertIntegral(Vec3(0.0), n, tri);
    EXPECT_NEAR(mine, lambertFactor(Vec3(0.0), n, tri), 1e-12 * (1 + mine));
  }
}

Object quad(const std::string& id, std::vector<Vec3> corners) {
  Object o;
  o.id = id;
  o.vertices = std::move(corners);
  o.faces = {{0, 1, 2, 3}};
  return o;
}

// Floor at y = 0, a 1×1 light at y = 3 facing down, and a horizontal square
// occluder at y = 1 facing up (towards the light) or down.
Scene floorLightOccluder(bool occluderFacesLight, double half) {
  Light light;
  light.id = "light";
  light.polygon = {{-0.5, 3, -0.5}, {0.5, 3, -0.5}, {0.5, 3, 0.5}, {-0.5, 3, 0.5}};
  light.radiance = Vec3(10);
  std::vector<Vec3> up{{-half, 1, -half}, {-half, 1, half}, {half, 1, half}, {half, 1, -half}};
  if (!occluderFacesLight) std::reverse(up.begin(), up.end());
  return Scene({light}, {},
               {quad("floor", {{-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}}), quad("occ", up)});
}

TEST(Backprojection, LitUmbraPenumbraAndComparisons) {
  const Scene scene = floorLightOccluder(true, 0.25);
  const Vec3 n(0, 1, 0);
  const ExactReference reference(scene);
  const std::vector<FaceId> occ{scene.faces()[1].id};
  // Under the occluder's centre: the 0.5 square at y=1 projects from (0,0,0) onto
  // a 1.5 square at y=3, hiding the whole light.
  const LightVisibleFactor umbra = backproject(scene, 0, Vec3(0.0), n, occ);
  EXPECT_EQ(umbra.lightClass, LightClass::Umbra);
  EXPECT_EQ(umbra.visibleFactor, 0.0);
  EXPECT_EQ(umbra.comparisons, 1u);
  // Penumbra, and the value matches the reference.
  const Vec3 p(0.3, 0, 0.1);
  const LightVisibleFactor pen = backproject(scene, 0, p, n, occ);
  EXPECT_EQ(pen.lightClass, LightClass::Penumbra);
  const LightVisibility truth = reference.visibility(p, n, 0);
  EXPECT_NEAR(pen.visibleFactor, truth.visibleFactor, 1e-12);
  EXPECT_NEAR(pen.unoccludedFactor, truth.unoccludedFactor, 1e-12);
  // Far away the cone misses the occluder: no comparison, lit.
  const LightVisibleFactor lit = backproject(scene, 0, Vec3(3.5, 0, 3.5), n, occ);
  EXPECT_EQ(lit.lightClass, LightClass::Lit);
  EXPECT_EQ(lit.comparisons, 0u);
  EXPECT_EQ(lit.visibleFactor, lit.unoccludedFactor);
}

TEST(Backprojection, OccluderFacingAwayNeverBlocks) {
  const Scene scene = floorLightOccluder(false, 0.25);
  const LightVisibleFactor v = backproject(scene, 0, Vec3(0.0), Vec3(0, 1, 0), {&scene.faces()[1].id, 1});
  EXPECT_EQ(v.lightClass, LightClass::Lit);
  EXPECT_EQ(v.comparisons, 0u);
}

TEST(Backprojection, FaceWhosePlaneContainsPointNeverBlocks) {
  const Scene scene = floorLightOccluder(true, 0.25);
  // A point on the occluder's own plane (beside it, looking up) and on its surface.
  for (const Vec3& p : {Vec3(0.6, 1, 0), Vec3(0.1, 1, 0.1)}) {
    const LightVisibleFactor v = backproject(scene, 0, p, Vec3(0, 1, 0), {&scene.faces()[1].id, 1});
    EXPECT_EQ(v.lightClass, LightClass::Lit);
    EXPECT_EQ(v.comparisons, 0u);
  }
}

TEST(Backprojection, LightBehindPointDoesNotApply) {
  const Scene scene = floorLightOccluder(true, 0.25);
  // Above the light, and a receiver facing away from it.
  EXPECT_FALSE(backproject(scene, 0, Vec3(0, 3.5, 0), Vec3(0, 1, 0), {}).applies);
  EXPECT_FALSE(backproject(scene, 0, Vec3(0, 1, 0), Vec3(0, -1, 0), {}).applies);
  // A wall point whose plane halves the light.
  const Vec3 p(0, 1, 0), n(1, 0, 0);
  const LightVisibleFactor half = backproject(scene, 0, p, n, {});
  EXPECT_TRUE(half.applies);
  EXPECT_NEAR(half.visibleFactor, ExactReference(scene).visibility(p, n, 0).visibleFactor, 1e-13);
}

}  // namespace
}  // namespace penumbra
