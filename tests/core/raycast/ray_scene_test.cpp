#include "core/raycast/ray_scene.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <random>

namespace penumbra {
namespace {

// Embree traces in float: hit points agree with double geometry to ~1e-7 of the
// coordinates; tests allow 1e-5 of the scene's size.
constexpr double kFloatTolerance = 1e-5;

Object quad(const std::string& id, Polygon3 corners) {
  Object object;
  object.id = id;
  object.vertices = std::move(corners);
  object.faces = {{0, 1, 2, 3}};
  return object;
}

Object unitCube(const std::string& id) {
  Object cube;
  cube.id = id;
  for (int i = 0; i < 8; ++i)
    cube.vertices.push_back(Vec3((i & 1) ? 1 : 0, (i & 2) ? 1 : 0, (i & 4) ? 1 : 0));
  // CCW seen from outside.
  cube.faces = {{0, 4, 6, 2}, {1, 3, 7, 5},   // x = 0, x = 1
                {0, 1, 5, 4}, {2, 6, 7, 3},   // y = 0, y = 1
                {0, 2, 3, 1}, {4, 5, 7, 6}};  // z = 0, z = 1
  return cube;
}

Light ceilingLight() {
  Light light;
  light.id = "light";
  light.polygon = {{-0.5, 4, -0.5}, {0.5, 4, -0.5}, {0.5, 4, 0.5}, {-0.5, 4, 0.5}};
  light.radiance = Vec3(1.0);
  return light;
}

Scene sceneOf(std::vector<Object> objects) {
  return Scene({ceilingLight()}, {}, std::move(objects));
}

// A 2×2 quad in the plane z = 0 facing +z.
Object quadFacingPlusZ() { return quad("q", {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}); }

TEST(RayScene, CubeFacesAreOutward) {
  const Scene scene = sceneOf({unitCube("c")});
  for (const Face& face : scene.faces())
    EXPECT_GT(glm::dot(face.plane.normal, centroid(face.polygon) - Vec3(0.5)), 0);
}

TEST(RayScene, QuadBlocksOnlyFromBehind) {
  const Scene scene = sceneOf({quadFacingPlusZ()});
  ASSERT_GT(scene.faces()[0].plane.normal.z, 0);
  const RayScene rays(scene);
  // Back to front: blocked.
  EXPECT_TRUE(rays.occluded({0.2, 0.1, -1}, {-0.3, 0.2, 1}));
  EXPECT_EQ(rays.blockers({0.2, 0.1, -1}, {-0.3, 0.2, 1}), std::vector<uint32_t>{0});
  // Front to back: q is behind the face, never blocked.
  EXPECT_FALSE(rays.occluded({-0.3, 0.2, 1}, {0.2, 0.1, -1}));
  // Missing the polygon, or not reaching its plane: not blocked.
  EXPECT_FALSE(rays.occluded({3, 0, -1}, {3, 0, 1}));
  EXPECT_FALSE(rays.occluded({0, 0, -2}, {0, 0, -1}));
  EXPECT_FALSE(rays.occluded({0, 0, 1}, {0, 0, 2}));
}

TEST(RayScene, FaceContainingPNeverBlocksIt) {
  const Scene scene = sceneOf({quadFacingPlusZ()});
  const RayScene rays(scene);
  const double eps = scene.tolerance().onPlane();
  const Vec3 q{0.1, -0.2, 1};
  // p on the face itself, and just behind it within the tolerance.
  EXPECT_FALSE(rays.occluded({0, 0, 0}, q));
  EXPECT_FALSE(rays.occluded({0.3, 0.4, -0.5 * eps}, q));
  // Just beyond the tolerance behind the face: the face blocks.
  EXPECT_TRUE(rays.occluded({0.3, 0.4, -4 * eps}, q));
  // q on the face's plane is not strictly in front of it: not blocked.
  EXPECT_FALSE(rays.occluded({0.3, 0.4, -1}, {0.2, 0.1, 0}));
  EXPECT_FALSE(rays.occluded({0.3, 0.4, -1}, {0.2, 0.1, 0.5 * eps}));
  EXPECT_TRUE(rays.occluded({0.3, 0.4, -1}, {0.2, 0.1, 4 * eps}));
}

TEST(RayScene, TouchingAndCoplanarFacesDoNotBlock) {
  // A unit cube resting on a floor made of two coplanar quads that meet at x = 1.
  const Scene scene = sceneOf({quad("floor_a", {{-3, 0, -3}, {-3, 0, 3}, {1, 0, 3}, {1, 0, -3}}),
                               quad("floor_b", {{1, 0, -3}, {1, 0, 3}, {3, 0, 3}, {3, 0, -3}}),
                               unitCube("cube")});
  ASSERT_GT(scene.faces()[0].plane.normal.y, 0);
  ASSERT_GT(scene.faces()[1].plane.normal.y, 0);
  const RayScene rays(scene);
  // p at the foot of the cube's +x face, on the shared floor edge: the floor
  // quads, the cube's bottom and its +x face all contain p. The segment runs
  // through the cube and leaves by its top, which alone blocks.
  const Vec3 p{1, 0, 0.5};
  const auto top = std::find_if(scene.faces().begin(), scene.faces().end(), [](const Face& f) {
    return f.id.object == 2 && f.plane.normal.y > 0.5;
  });
  const uint32_t topIndex = uint32_t(top - scene.faces().begin());
  EXPECT_EQ(rays.blockers(p, {-1, 3, 0.5}), std::vector<uint32_t>{topIndex});
  // Leaving the cube's foot outward and upward: nothing blocks.
  EXPECT_FALSE(rays.occluded(p, {3, 3, 0.5}));
  // From the floor beyond: the ray enters the +x face from its front (no block)
  // and leaves through the top from behind (block).
  EXPECT_EQ(rays.blockers({2, 0, 0.5}, {-2, 3, 0.5}), std::vector<uint32_t>{topIndex});
  // A point on the cube's top sees straight up; the top face contains it.
  EXPECT_FALSE(rays.occluded({0.5, 1, 0.5}, {0.2, 4, 0.1}));
  // A point on the floor beside the cube, light on the far side: blocked by the cube.
  EXPECT_TRUE(rays.occluded({1.5, 0, 0.5}, {-1.5, 1.5, 0.5}));
}

TEST(RayScene, ClosestHitReturnsTheNearestFace) {
  const Scene scene = sceneOf({quadFacingPlusZ(),
                               quad("far", {{-1, -1, 2}, {1, -1, 2}, {1, 1, 2}, {-1, 1, 2}})});
  const RayScene rays(scene);
  const auto fromFront = rays.intersect({0.25, 0.5, 5}, {0, 0, -1});
  ASSERT_TRUE(fromFront);
  EXPECT_EQ(fromFront->face, (FaceId{1, 0}));
  EXPECT_NEAR(fromFront->t, 3, kFloatTolerance);
  EXPECT_TRUE(fromFront->frontFacing);
  EXPECT_EQ(fromFront->position.z, 2);  // snapped onto the double plane

  const auto fromBehind = rays.intersect({0.25, 0.5, -5}, {0, 0, 2});
  ASSERT_TRUE(fromBehind);
  EXPECT_EQ(fromBehind->face, (FaceId{0, 0}));
  EXPECT_NEAR(fromBehind->t, 2.5, kFloatTolerance);
  EXPECT_FALSE(fromBehind->frontFacing);

  // Barycentrics reconstruct the hit point in its fan triangle.
  const Polygon3& poly = scene.faces()[fromBehind->faceIndex].polygon;
  const size_t k = fromBehind->fanTriangle + 1;
  const Vec2 b = fromBehind->barycentric;
  const Vec3 rebuilt = (1 - b.x - b.y) * poly[0] + b.x * poly[k] + b.y * poly[k + 1];
  EXPECT_LT(glm::length(rebuilt - fromBehind->position), kFloatTolerance);

  // tFar short of the first face: no hit. A ray away from both: no hit.
  EXPECT_FALSE(rays.intersect({0.25, 0.5, -5}, {0, 0, 1}, 0, 4.5));
  EXPECT_FALSE(rays.intersect({0.25, 0.5, 5}, {0, 0, 1}));
}

TEST(RayScene, TransformedObjectIsHitWhereSceneFacesAre) {
  Object cube = unitCube("cube");
  cube.transform.translate = Vec3(1, 2, 3);
  cube.transform.rotateDeg = Vec3(10, 30, 45);
  cube.transform.scale = Vec3(2, 0.5, 1.5);
  const Scene scene = sceneOf({cube});
  const RayScene rays(scene);
  const double size = scene.tolerance().sceneSize;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.05, 1.0);
  for (const Face& face : scene.faces()) {
    for (int trial = 0; trial < 20; ++trial) {
      // A random interior point: positive weights on the convex polygon's corners.
      Vec3 point{0.0};
      double total = 0;
      for (const Vec3& v : face.polygon) {
        const double w = unit(rng);
        point += w * v;
        total += w;
      }
      point /= total;
      const Vec3 origin = point + face.plane.normal;
      const auto hit = rays.intersect(origin, -face.plane.normal);
      ASSERT_TRUE(hit);
      EXPECT_EQ(hit->face, face.id);
      EXPECT_TRUE(hit->frontFacing);
      EXPECT_LT(glm::length(hit->position - point), kFloatTolerance * size);
      // From inside the cube the face blocks a segment leaving through it.
      const Vec3 inside = 0.5 * (point + centroid(face.polygon)) - 0.05 * face.plane.normal;
      EXPECT_EQ(rays.blockers(inside, origin), std::vector<uint32_t>{uint32_t(&face - &scene.faces()[0])});
    }
  }
}

TEST(RayScene, ConcurrentQueriesMatchSequentialOnes) {
  const Scene scene = sceneOf({unitCube("cube"), quadFacingPlusZ()});
  const RayScene rays(scene);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> coord(-2, 3);
  const size_t count = 4000;
  std::vector<Vec3> from(count), to(count);
  for (size_t i = 0; i < count; ++i) {
    from[i] = Vec3(coord(rng), coord(rng), coord(rng));
    to[i] = Vec3(coord(rng), coord(rng), coord(rng));
  }
  std::vector<char> sequential(count), parallel(count);
  for (size_t i = 0; i < count; ++i) sequential[i] = rays.occluded(from[i], to[i]);
  tbb::parallel_for(size_t(0), count, [&](size_t i) { parallel[i] = rays.occluded(from[i], to[i]); });
  EXPECT_EQ(sequential, parallel);
  // Both outcomes occur, and occluded() agrees with the list of blockers.
  size_t blocked = 0;
  for (size_t i = 0; i < count; ++i) {
    blocked += sequential[i];
    EXPECT_EQ(bool(sequential[i]), !rays.blockers(from[i], to[i]).empty());
  }
  EXPECT_GT(blocked, 0u);
  EXPECT_LT(blocked, count);
}

}  // namespace
}  // namespace penumbra
