// The full build on dense rooms (boxes floating at random, dozens of faces covering
// a vertex) against the independent exact reference: every DM vertex's value equals
// the brute-force reference at 1e-9 relative, and the triangles tile every receiver.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "bench/lib/dense_scene.h"
#include "core/engine/engine.h"
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

}  // namespace
}  // namespace penumbra
