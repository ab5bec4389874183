// The full build on dense rooms (boxes floating at random, dozens of faces covering
// a vertex) against the independent exact reference: every DM vertex's value equals
// the brute-force reference at 1e-9 relative, and the triangles tile every receiver;
// boxes dragged through them incrementally equal a rebuild after every frame.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "bench/lib/dense_drag.h"
#include "core/engine/engine.h"
#include "scenegen/dense_scene.h"
#include "tests/core/engine/incremental_compare.h"
#include "tests/core/engine/reference_check.h"

namespace penumbra {
namespace {

using testing::ReferenceCheck;

ReferenceCheck checkDenseRoom(int boxes, uint64_t seed) {
  Engine engine(makeDenseScene({.boxes = boxes, .seed = seed}));
  const std::string label = "N " + std::to_string(boxes) + " seed " + std::to_string(seed);
  const ReferenceCheck out = testing::checkAgainstReference(engine, label);
  std::printf("dense N=%d seed %llu: %zu vertices, %zu value errors, %zu class errors\n", boxes,
              (unsigned long long)seed, out.vertices, out.valueErrors, out.classErrors);
  return out;
}

TEST(DenseReference, SmallRoomsEverySeed) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const ReferenceCheck c = checkDenseRoom(int(10 + 5 * seed), seed);
    EXPECT_EQ(c.valueErrors, 0u);
    EXPECT_EQ(c.classErrors, 0u);
  }
}

TEST(DenseReference, Dense150) {
  const ReferenceCheck c = checkDenseRoom(150, 1);
  EXPECT_EQ(c.valueErrors, 0u);
  EXPECT_EQ(c.classErrors, 0u);
}

TEST(DenseReference, Dense300) {
  const ReferenceCheck c = checkDenseRoom(300, 1);
  EXPECT_GT(c.vertices, 100000u);
  EXPECT_EQ(c.valueErrors, 0u);
  EXPECT_EQ(c.classErrors, 0u);
}

// The bench's move-one-box script (the box under the light, whose shadow covers the
// floor and the boxes below) on small dense rooms: after every frame the incremental
// engine equals a rebuild of its scene (values at each other's vertices, classes and
// values at random points, segments), and at the end the exact reference.
TEST(DenseIncremental, DraggedBoxEqualsRebuild) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    const std::string label = "dense 30 seed " + std::to_string(seed);
    SCOPED_TRACE(label);
    Engine engine(makeDenseScene({.boxes = 30, .seed = seed}));
    const EditScript script = denseDragScript(engine.scene(), 6, seed);
    size_t frame = 0;
    for (const Frame& f : script.frames) {
      const FrameResult result = engine.apply(f);
      EXPECT_FALSE(result.fullRebuild);
      EXPECT_GT(result.verticesRelit, 0u);
      const Engine rebuilt(engine.scene());
      const double peak = std::max(testing::peakIrradiance(rebuilt), 1e-300);
      const testing::EngineDiff diff = testing::compareEngines(engine, rebuilt, peak, 40, seed * 100 + ++frame);
      EXPECT_EQ(diff.errors(), 0u) << "frame " << frame << ": " << diff.firstProblem;
      EXPECT_GT(diff.matchedVertices, 0u);
    }
    const ReferenceCheck c = testing::checkAgainstReference(engine, label);
    EXPECT_EQ(c.valueErrors, 0u);
    EXPECT_EQ(c.classErrors, 0u);
  }
}

}  // namespace
}  // namespace penumbra
