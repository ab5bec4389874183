// The large-frame switch of Engine::apply: a frame editing more than a set share of
// a large scene's faces rebuilds the engine and says so (FrameResult::fullRebuild,
// every receiver counted in treeRebuilds); small frames and small scenes stay
// incremental. Either way the state equals a fresh build of the new scene.
#include <gtest/gtest.h>

#include "bench/lib/cubes_scene.h"
#include "bench/lib/edit_scripts.h"
#include "core/engine/engine.h"
#include "tests/core/engine/incremental_compare.h"

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

}  // namespace
}  // namespace penumbra
