// The large-frame switch of Engine::apply: a frame undoing more than a set share of a large
// scene's cast pairs (its work, not its faces) rebuilds the engine and says so
// (FrameResult::fullRebuild, every receiver counted in treeRebuilds); small frames, frames of
// many faces that shadow little, and small scenes stay incremental. Either way the state
// equals a fresh build of the new scene.
#include <gtest/gtest.h>

#include "bench/lib/edit_scripts.h"
#include "core/engine/engine.h"
#include "scenegen/cubes_scene.h"
#include "tests/core/engine/incremental_compare.h"
#include "tests/core/illum/random_meshes.h"

namespace penumbra {
namespace {

Scene largeScene() {
  CubesSceneOptions options;
  options.cubes = 80;  // 486 faces: above the switch's minimum scene size
  options.seed = 3;
  return makeCubesScene(options);
}

void expectEqualsRebuild(const Engine& engine, const char* what) {
  const Engine fresh(engine.scene());
  const testing::EngineDiff diff =
      testing::compareEngines(engine, fresh, testing::peakIrradiance(fresh), 200, 7);
  EXPECT_EQ(diff.errors(), 0u) << what << ": " << diff.firstProblem;
}

TEST(LargeFrameRebuild, MovingAThirdOfTheFacesRebuildsAndSaysSo) {
  const Scene scene = largeScene();
  Engine engine(scene);
  const EditScript script = moveShareScript(scene, 0.30, 1, 5);
  ASSERT_GT(script.faceShare, 0.15);
  const FrameResult result = engine.apply(script.frames[0]);
  EXPECT_TRUE(result.fullRebuild);
  EXPECT_EQ(result.treeRebuilds, engine.receivers().size());
  EXPECT_EQ(result.changedReceivers.size(), engine.receivers().size());
  EXPECT_EQ(engine.version(), 1u);
  ASSERT_NO_THROW(engine.validate());
  expectEqualsRebuild(engine, "after a 30% move");
}

TEST(LargeFrameRebuild, OneCubeStaysIncremental) {
  const Scene scene = largeScene();
  Engine engine(scene);
  const EditScript script = dragScript(scene, 3, 5);
  for (const Frame& frame : script.frames) {
    const FrameResult result = engine.apply(frame);
    EXPECT_FALSE(result.fullRebuild);
    EXPECT_LT(result.treeRebuilds, engine.receivers().size());
    ASSERT_NO_THROW(engine.validate());
  }
  expectEqualsRebuild(engine, "after dragging one cube");
}

TEST(LargeFrameRebuild, SmallScenesStayIncrementalWhateverTheShare) {
  const Scene scene = makeCubesScene(CubesSceneOptions{});  // 15 cubes, 96 faces
  Engine engine(scene);
  const EditScript script = moveShareScript(scene, 0.30, 1, 5);
  const FrameResult result = engine.apply(script.frames[0]);
  EXPECT_FALSE(result.fullRebuild);
  ASSERT_NO_THROW(engine.validate());
  expectEqualsRebuild(engine, "after a 30% move of a small scene");
}

// The large scene with a tessellated model of 528 faces (more than the room's 486), bumped
// (non-convex: its faces shadow each other) or not.
Scene largeSceneWith(Vec3 centre, double radius, double bump) {
  Scene scene = largeScene();
  scene.addObject(test::bumpySphere("model", centre, radius, 12, bump, 4));
  return scene;
}

Frame moveModel(Vec3 by) {
  Edit move;
  move.op = Edit::Op::Move;
  move.id = "model";
  move.transform.translate = by;
  return Frame{{move}};
}

// The switch counts work, not faces: a convex model (it casts whole, its faces shadow no other
// of its own) in a corner shadows little, so dragging it edits more than half the faces and
// still stays incremental.
TEST(LargeFrameRebuild, AManyFacedModelThatShadowsLittleMovesIncrementally) {
  const double corner = cubesRoom(CubesSceneOptions{.cubes = 80, .seed = 3}).side / 2 - 0.3;
  Engine engine(largeSceneWith(Vec3(corner, 0.2, corner), 0.12, 0.0));
  for (int f = 1; f <= 3; ++f) {
    const FrameResult result = engine.apply(moveModel(Vec3(-0.03 * f, 0, -0.02 * f)));
    EXPECT_FALSE(result.fullRebuild) << "frame " << f;
    ASSERT_NO_THROW(engine.validate());
  }
  expectEqualsRebuild(engine, "after dragging the model in the corner");
}

// A bumped one, its faces shadowing each other, holds most of the scene's cast pairs: a move
// rebuilds.
TEST(LargeFrameRebuild, AModelHoldingMostShadowsRebuildsWhenMoved) {
  const double corner = cubesRoom(CubesSceneOptions{.cubes = 80, .seed = 3}).side / 2 - 0.3;
  Engine engine(largeSceneWith(Vec3(corner, 0.2, corner), 0.12, 0.3));
  const FrameResult result = engine.apply(moveModel(Vec3(-0.03, 0, -0.02)));
  EXPECT_TRUE(result.fullRebuild);
  EXPECT_EQ(result.treeRebuilds, engine.receivers().size());
  ASSERT_NO_THROW(engine.validate());
  expectEqualsRebuild(engine, "after moving the large model");
}

// An added object has no cast pairs yet: adding the bumped model (more than half the faces)
// rebuilds by its share of the faces.
TEST(LargeFrameRebuild, AddingAModelOfMostFacesRebuilds) {
  const double corner = cubesRoom(CubesSceneOptions{.cubes = 80, .seed = 3}).side / 2 - 0.3;
  const Scene withModel = largeSceneWith(Vec3(corner, 0.2, corner), 0.12, 0.3);
  Engine engine(largeScene());
  Edit add;
  add.op = Edit::Op::Add;
  add.object = withModel.objects()[*withModel.findObject("model")];
  const FrameResult result = engine.apply(Frame{{add}});
  EXPECT_TRUE(result.fullRebuild);
  ASSERT_NO_THROW(engine.validate());
  expectEqualsRebuild(engine, "after adding the model");
}

}  // namespace
}  // namespace penumbra
