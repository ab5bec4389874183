// Closed convex objects in the engine: a tessellated sphere over the floor under an area
// light, built without casting its faces on each other, matches the exact reference at
// every vertex; edits (the sphere moved, a box added under it, then moved against it)
// equal a rebuild and the reference; an open sphere's pairs are still cast.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/engine/engine.h"
#include "scenegen/scene_parts.h"
#include "scenegen/sphere_scene.h"
#include "tests/core/engine/incremental_compare.h"
#include "tests/core/engine/reference_check.h"

namespace penumbra {
namespace {

// 288 faces (12 × 24), off the light's axis so no symmetry hides an error.
Scene sphereScene() {
  return makeSphereScene({.faces = 288, .radius = 0.35, .centre = Vec3(0.4, 0.7, -0.3)});
}

void expectExact(Engine& engine, const std::string& label) {
  const testing::ReferenceCheck c = testing::checkAgainstReference(engine, label);
  std::printf("%s: %zu vertices, %zu value errors, %zu class errors\n", label.c_str(), c.vertices,
              c.valueErrors, c.classErrors);
  EXPECT_GT(c.vertices, 1000u) << label;
  EXPECT_EQ(c.valueErrors, 0u) << label;
  EXPECT_EQ(c.classErrors, 0u) << label;
}

TEST(ClosedConvexEngine, SphereOverFloorMatchesReference) {
  Engine engine(sphereScene());
  const Scene& scene = engine.scene();
  const uint32_t sphere = scene.handleOf(*scene.findObject("sphere"));
  ASSERT_TRUE(scene.isClosedConvex(sphere));
  const BuildStats& s = engine.stats();
  std::printf(
      "sphere 288: %zu candidate pairs, %zu closed convex, %zu cast attempts, %zu with shadow\n",
      s.candidatePairs, s.closedConvexPairs, s.castAttempts, s.pairsWithShadow);
  // Most candidate pairs are sphere-sphere; none of them is cast.
  EXPECT_GT(s.closedConvexPairs, s.candidatePairs / 2);
  EXPECT_LE(s.castAttempts, 2 * (s.candidatePairs - s.closedConvexPairs));
  for (const Face& f : scene.faces()) {
    if (f.id.object != sphere) continue;
    for (FaceId target : engine.castOn(f.id))
      EXPECT_NE(target.object, sphere) << "sphere face " << f.id.face << " cast on " << target.face;
  }
  expectExact(engine, "sphere 288");
}

TEST(ClosedConvexEngine, EditsEqualRebuildAndReference) {
  Engine engine(sphereScene());
  Edit move;
  move.op = Edit::Op::Move;
  move.id = "sphere";
  move.transform.translate = Vec3(-0.3, 0.15, 0.2);
  move.transform.rotateDeg = Vec3(10, 25, 0);
  Edit add;
  add.op = Edit::Op::Add;
  add.object.id = "box";
  addBox(add.object, Vec3(-0.5, 0, -0.8), Vec3(0.1, 0.3, -0.2));
  Edit touch;  // the box raised and shifted under the sphere
  touch.op = Edit::Op::Move;
  touch.id = "box";
  touch.transform.translate = Vec3(0.1, 0.2, 0.05);
  const Frame frames[] = {Frame{{move}}, Frame{{add}}, Frame{{touch}}};
  int f = 0;
  for (const Frame& frame : frames) {
    const FrameResult result = engine.apply(frame);
    EXPECT_FALSE(result.fullRebuild);
    EXPECT_EQ(result.treeRebuilds, 0u);
    engine.validate();
    Engine rebuilt(engine.scene());
    const testing::EngineDiff diff = testing::compareEngines(
        engine, rebuilt, testing::peakIrradiance(rebuilt), 200, uint64_t(f));
    EXPECT_EQ(diff.errors(), 0u) << "frame " << f << ": " << diff.firstProblem;
    ++f;
  }
  // Each frame equals a rebuild (above), and a rebuild of this sphere is exact
  // (SphereOverFloorMatchesReference): the reference at every vertex once, at the end,
  // keeps the test at a third of its time.
  expectExact(engine, "sphere after the frames");
}

// The same sphere with one face missing is open: its pairs are cast as any others (they
// find no shadow, the sphere being convex) and the result is exact all the same.
TEST(ClosedConvexEngine, OpenSphereStillCastsOnItself) {
  const Scene closed = sphereScene();
  std::vector<Object> objects = closed.objects();
  Object& sphere = objects.back();
  ASSERT_EQ(sphere.id, "sphere");
  sphere.faces.erase(sphere.faces.begin() + 30);
  Engine engine(Scene(closed.lights(), closed.materials(), objects, closed.camera()));
  EXPECT_FALSE(engine.scene().isClosedConvex(engine.scene().handleOf(objects.size() - 1)));
  EXPECT_EQ(engine.stats().closedConvexPairs, 0u);
  expectExact(engine, "open sphere 287");
}

}  // namespace
}  // namespace penumbra
