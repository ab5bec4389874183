// Umbra culling in the DM-trees (DmTree::insert): on seeded cube rooms (cubes stacked and
// resting on each other, one or two lights) some shadows are culled, the trees hold fewer
// vertices than with culling off, and every vertex equals the exact reference and the
// unculled engine's value at its point.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "core/engine/engine.h"
#include "scenegen/cubes_scene.h"
#include "tests/core/engine/incremental_compare.h"
#include "tests/core/engine/reference_check.h"

namespace penumbra {
namespace {

TEST(UmbraCulling, CulledRoomsEqualTheUnculledEngineAndTheReference) {
  size_t culled = 0, verticesOn = 0, verticesOff = 0;
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Scene scene = makeCubesScene(mixedCubesOptions(seed));
    EngineSettings off;
    off.umbraCulling = false;
    Engine on(scene);
    const Engine unculled(scene, off);
    for (const Engine::Receiver& r : on.receivers()) {
      culled += r.tree.culledOccluders();
      verticesOn += r.tree.vertexCount();
    }
    for (const Engine::Receiver& r : unculled.receivers()) verticesOff += r.tree.vertexCount();
    const double peak = std::max(testing::peakIrradiance(unculled), 1e-300);
    const testing::EngineDiff diff = testing::compareEngines(on, unculled, peak, 200, seed);
    EXPECT_EQ(diff.errors(), 0u) << diff.firstProblem;
    const testing::ReferenceCheck check = testing::checkAgainstReference(on, "seed " + std::to_string(seed));
    EXPECT_EQ(check.valueErrors, 0u);
  }
  std::printf("12 rooms: %zu shadows culled somewhere; DM vertices %zu with culling, %zu without\n", culled,
              verticesOn, verticesOff);
  EXPECT_GT(culled, 0u);
  EXPECT_LT(verticesOn, verticesOff);
}

}  // namespace
}  // namespace penumbra
