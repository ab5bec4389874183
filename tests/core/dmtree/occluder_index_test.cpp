// OccluderIndex: the frozen BSP gives, at any point of a receiver, exactly the occluder list of
// the cell DmTree::locate finds (light-plane entries left out), before and after edits.
#include "core/dmtree/occluder_index.h"

#include <gtest/gtest.h>

#include <random>

#include "core/engine/engine.h"
#include "scenegen/cubes_scene.h"

namespace penumbra {
namespace {

// Every receiver of the engine: 200 seeded points inside its face (and its corners), index vs tree.
void expectIndexMatchesTree(const Engine& engine, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  size_t nonEmpty = 0;
  for (const Engine::Receiver& r : engine.receivers()) {
    const OccluderIndex index(r.tree, r.frame);
    const Polygon3* polygon = nullptr;
    for (const Face& f : engine.scene().faces())
      if (f.id == r.face) polygon = &f.polygon;
    ASSERT_NE(polygon, nullptr);
    std::vector<Vec3> points(polygon->begin(), polygon->end());
    for (int i = 0; i < 200; ++i) {  // convex combinations of three corners
      const size_t n = polygon->size();
      double a = u(rng), b = u(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const size_t k = 1 + size_t(u(rng) * double(n - 2)) % (n - 2);
      points.push_back((*polygon)[0] + a * ((*polygon)[k] - (*polygon)[0]) +
                       b * ((*polygon)[k + 1] - (*polygon)[0]));
    }
    for (const Vec3& p : points)
      for (uint32_t light = 0; light < engine.scene().lights().size(); ++light) {
        std::vector<FaceId> expected, got;
        for (const OccluderEntry& e : r.tree.occluders(r.tree.locate(r.frame.to2D(p))))
          if (e.light == light && e.face != kLightPlaneOccluder) expected.push_back(e.face);
        index.occluders(p, light, got);
        ASSERT_EQ(got, expected) << "receiver " << r.face.object << "/" << r.face.face;
        nonEmpty += !got.empty();
      }
  }
  EXPECT_GT(nonEmpty, 100u);  // the scene has shadows: the lists are not all empty
}

TEST(OccluderIndex, GivesTheTreesCellListEverywhere) {
  CubesSceneOptions options;
  options.cubes = 12;
  options.twoLights = true;
  Engine engine(makeCubesScene(options));
  expectIndexMatchesTree(engine, 1);
}

TEST(OccluderIndex, FollowsTheTreeAfterMoves) {
  CubesSceneOptions options;
  options.cubes = 8;
  options.subjectCube = true;
  Engine engine(makeCubesScene(options));
  for (int step = 1; step <= 3; ++step) {
    Edit move;
    move.op = Edit::Op::Move;
    move.id = kSubjectCubeId;
    move.transform = engine.scene().objects()[*engine.scene().findObject(kSubjectCubeId)].transform;
    move.transform.translate.z += 0.3 * step;
    engine.apply(Frame{{move}});
    expectIndexMatchesTree(engine, uint64_t(step));
  }
}

TEST(OccluderIndex, ATreeWithoutSplitsIsOneCell) {
  Light light{"l", {{-0.5, 3, -0.5}, {0.5, 3, -0.5}, {0.5, 3, 0.5}, {-0.5, 3, 0.5}}, Vec3(1)};
  Object floor;
  floor.id = "floor";
  floor.vertices = {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}};
  floor.faces = {{0, 1, 2, 3}};
  Engine engine(Scene({light}, {}, {floor}));
  ASSERT_EQ(engine.receivers().size(), 1u);
  const OccluderIndex index(engine.receivers()[0].tree, engine.receivers()[0].frame);
  std::vector<FaceId> out;
  index.occluders(Vec3(0.2, 0, 0.3), 0, out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(index.nodeCount(), engine.receivers()[0].tree.internalNodeCount());
}

}  // namespace
}  // namespace penumbra
