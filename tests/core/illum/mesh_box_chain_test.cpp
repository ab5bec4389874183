// What a mesh's faces do over a box (mesh_box_chain.h): for every point of the box, the
// chain of the faces behind all of it plus the crossing faces the point is behind covers
// each light point as often as the chain of every face the point is behind, on seeded
// non-convex, open and inconsistently oriented meshes and random boxes; and the per-thread
// memo answers as the box computed alone, whatever was asked before (issue 35). Boxes with
// faces a point decides itself (`special`) are checked by value in mesh_chain_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>

#include "core/illum/mesh_box_chain.h"
#include "core/illum/shadow_chain.h"
#include "core/scene/mesh_topology.h"
#include "tests/core/illum/random_meshes.h"

namespace penumbra {
namespace {

// The chain of the faces p lies more than onPlane behind, each one (no box).
std::vector<ChainEdge> chainOfEveryFace(const MeshTopology& mesh, const Vec3& p, const Plane& lightPlane,
                                        const PlaneFrame& frame, const Tolerance& tolerance) {
  std::vector<uint32_t> behind;
  for (uint32_t i = 0; i < mesh.clusterPlanes.size(); ++i)
    if (mesh.clusterPlanes[i].signedDistance(p) < -tolerance.onPlane()) behind.push_back(mesh.clusterFaces[i]);
  std::vector<ChainEdge> chain;
  appendShadowChain(mesh, behind, {}, {}, p, lightPlane, lightPlane.signedDistance(p), frame, tolerance.area(), chain);
  return chain;
}

std::vector<ChainEdge> chainOfBox(const MeshTopology& mesh, const MeshBoxChain& box, const Vec3& p,
                                  const Plane& lightPlane, const PlaneFrame& frame, const Tolerance& tolerance) {
  std::vector<uint32_t> behind;
  for (const uint32_t i : box.crossing)
    if (mesh.clusterPlanes[i].signedDistance(p) < -tolerance.onPlane()) behind.push_back(mesh.clusterFaces[i]);
  std::vector<ChainEdge> chain;
  appendShadowChain(mesh, behind, {}, box.behindAll, p, lightPlane, lightPlane.signedDistance(p), frame,
                    tolerance.area(), chain);
  return chain;
}

TEST(MeshBoxChain, EveryPointOfABoxCoversTheLightAsItsOwnFacesDo) {
  size_t usable = 0, unusable = 0, intoMeshBoxes = 0, covered = 0, compared = 0, crossing = 0, faces = 0;
  for (uint64_t seed = 1; seed <= 4; ++seed)
    for (const test::NamedMesh& named : test::seededMeshes(seed)) {
      const Object& object = named.mesh;
      const Light light = test::ceilingLight(0.4 + 0.15 * double(seed));
      const Scene scene({light}, {}, {object});
      const MeshTopology& mesh = *scene.meshTopology(scene.handleOf(0));
      const Tolerance tolerance = scene.tolerance();
      const Plane lightPlane = light.plane();
      const PlaneFrame frame = PlaneFrame::onPlane(lightPlane, light.polygon[0]);
      std::mt19937_64 rng(seed * 104729);
      std::uniform_real_distribution<double> u(-1.5, 1.5), size(0.005, 0.4), unit(0, 1);
      for (int b = 0; b < 30; ++b) {
        // A box around a stretch of the floor (y = 0), or one reaching into the mesh.
        const bool intoMesh = b % 10 == 9;
        const double half = size(rng);
        const Vec3 centre = intoMesh ? Vec3(0.0, 1.2, 0.0) : Vec3(u(rng), 0, u(rng));
        const Vec3 low = centre - Vec3(half), high = centre + Vec3(half);
        const MeshBoxChain box = makeMeshBoxChain(mesh, low, high, {0, 1, 0}, light.polygon, lightPlane, tolerance);
        if (intoMesh) {
          // The faces with a corner behind the receiver's plane through the box are decided
          // per point, or (most of them) the box is not used.
          EXPECT_TRUE(!box.usable || !box.special.empty()) << "a box reaching into the mesh, seed " << seed;
          unusable += !box.usable;
          ++intoMeshBoxes;
          continue;
        }
        ASSERT_TRUE(box.usable) << "a floor box under a floating mesh, seed " << seed;
        EXPECT_TRUE(box.special.empty()) << "every corner usable from a floor box, seed " << seed;
        ++usable;
        crossing += box.crossing.size(), faces += mesh.clusterFaces.size();
        for (int i = 0; i < 8; ++i) {
          const Vec3 p(low.x + (high.x - low.x) * unit(rng), 0, low.z + (high.z - low.z) * unit(rng));
          const auto own = chainOfEveryFace(mesh, p, lightPlane, frame, tolerance);
          const auto boxed = chainOfBox(mesh, box, p, lightPlane, frame, tolerance);
          for (int k = 0; k < 40; ++k) {
            const double s = unit(rng), t = unit(rng);
            const Vec3 q = light.polygon[0] + s * (light.polygon[1] - light.polygon[0]) + t * (light.polygon[3] - light.polygon[0]);
            const Vec2 x = frame.to2D(q), ray(std::cos(7.0 * k + 1), std::sin(7.0 * k + 1));
            const int expected = chainWinding(own, x, ray, own.size());
            EXPECT_EQ(chainWinding(boxed, x, ray, boxed.size()), expected) << named.name << " seed " << seed << " box " << b;
            covered += expected > 0;
            ++compared;
          }
        }
      }
    }
  EXPECT_EQ(intoMeshBoxes, 4u * 4u * 3u);
  EXPECT_GT(unusable, intoMeshBoxes / 2);
  // The boxes must exercise covered light points, and leave most faces out of the per-point pass.
  EXPECT_GT(covered, compared / 5);
  EXPECT_LT(crossing, faces / 3);
  EXPECT_EQ(usable, 4u * 4u * 27u);
}

// Floor points under a mesh resting on the floor: their box is a flat slab of its cube, so
// only the faces at the mesh's foot are special (a corner on the floor, or within the 1e-3 of
// p's height below 3 m that a point's own pass asks of each corner), not every face lower than
// the cube's top.
TEST(MeshBoxChain, AFloorBoxUnderARestingMeshLeavesOnlyItsFootSpecial) {
  size_t boxes = 0, special = 0;
  for (uint64_t seed = 1; seed <= 3; ++seed)
    for (test::NamedMesh& named : test::seededMeshes(seed)) {
      double lowest = INFINITY;
      for (const Vec3& v : named.mesh.vertices) lowest = std::min(lowest, v.y);
      for (Vec3& v : named.mesh.vertices) v.y -= lowest;
      const Light light = test::ceilingLight(0.5);
      const Scene scene({light}, {}, {named.mesh});
      const MeshTopology& mesh = *scene.meshTopology(scene.handleOf(0));
      const std::span<const Face> faces = scene.facesOfObject(scene.handleOf(0));
      std::mt19937_64 rng(seed);
      std::uniform_real_distribution<double> u(-1.2, 1.2);
      for (int i = 0; i < 40; ++i) {
        const MeshBoxChain* box =
            meshBoxChain(mesh, {u(rng), 0, u(rng)}, {0, 1, 0}, light.polygon, light.plane(), scene.tolerance());
        ASSERT_NE(box, nullptr);
        ASSERT_TRUE(box->usable) << named.name;
        ++boxes;
        for (const uint32_t k : box->special) {
          const Face& face = faces[mesh.clusterFaces[k]];
          const bool foot = std::any_of(face.polygon.begin(), face.polygon.end(), [](const Vec3& v) { return v.y < 0.0031; });
          EXPECT_TRUE(foot) << named.name << " seed " << seed;
          ++special;
        }
      }
    }
  EXPECT_GT(special, boxes);  // the foot is there to be decided
}

TEST(MeshBoxChain, TheMemoAnswersAsTheBoxAloneWhateverWasAskedBefore) {
  const Light light = test::ceilingLight(0.6);
  const Scene scene({light}, {}, {test::torus("m", {0.0, 1.3, 0.1}, 0.45, 0.15, 24, 10, 0.6)});
  const MeshTopology& mesh = *scene.meshTopology(scene.handleOf(0));
  const Plane lightPlane = light.plane();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::vector<Vec3> points;
  for (int i = 0; i < 200; ++i) points.push_back({u(rng), 0, u(rng)});
  auto ask = [&](const Vec3& p) {
    const MeshBoxChain* box = meshBoxChain(mesh, p, {0, 1, 0}, light.polygon, lightPlane, scene.tolerance());
    return box ? *box : MeshBoxChain{};
  };
  // Each point alone on a fresh thread, then all of them in a row (boxes evicted and made again).
  std::vector<MeshBoxChain> alone;
  for (const Vec3& p : points) std::thread([&] { alone.push_back(ask(p)); }).join();
  for (int round = 0; round < 2; ++round)
    for (size_t i = 0; i < points.size(); ++i) {
      const MeshBoxChain box = ask(points[i]);
      ASSERT_TRUE(box.usable) << i;
      EXPECT_EQ(box.crossing, alone[i].crossing) << i;
      EXPECT_EQ(box.behindAll, alone[i].behindAll) << i;
    }
}

}  // namespace
}  // namespace penumbra
