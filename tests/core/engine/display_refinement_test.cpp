// The error-bounded display mesh (core/mesh/cell_refinement.h, docs/DESIGN.md): at seeded random
// points of random scenes (cube rooms, a tessellated model), the direct light the mesh
// interpolates is within twice the tolerance of each point's local unshadowed level of the exact
// reference (ExactReference, no code shared with the engine); the same after random edit
// frames, where the kept mesh also equals the same engine's mesh meshed afresh, bit for bit.
// Without refinement the same check fails (it can fail).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <string>

#include "core/engine/engine.h"
#include "scenegen/cubes_scene.h"
#include "scenegen/model_scene.h"
#include "tests/core/engine/display_bound.h"
#include "tests/core/engine/incremental_compare.h"

namespace penumbra {
namespace {

using testing::BoundCheck;
using testing::checkBound;
using testing::expectSameAsAFreshMesh;

constexpr double kTolerance = EngineSettings::kRecommendedMeshTolerance;

EngineSettings refined() {
  EngineSettings settings;
  settings.meshTolerance = kTolerance;
  return settings;
}
constexpr double kSlack = 2;  // 1 % of the local level at the default 0.5 %

Scene modelScene(uint64_t seed) {
  ModelSceneOptions options;
  options.kind = seed % 2 ? ModelKind::TorusKnot : ModelKind::Blob;
  options.triangles = 400;
  options.rest = seed % 3 == 0;
  options.seed = seed;
  return makeModelScene(options);
}

TEST(DisplayRefinement, RandomPointsWithinTheToleranceOnCubeRooms) {
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    SCOPED_TRACE("cubes seed " + std::to_string(seed));
    Engine engine(makeCubesScene(mixedCubesOptions(seed)), refined());
    const Mesh mesh = engine.mesh();
    EXPECT_EQ(mesh.tolerance, kTolerance);
    const BoundCheck check = checkBound(engine, mesh, kTolerance, kSlack, seed);
    EXPECT_EQ(check.over, 0u) << check.first << " (worst " << check.worst << ", capped cells " << mesh.cappedCells
                              << ")";
  }
}

TEST(DisplayRefinement, RandomPointsWithinTheToleranceOnModels) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE("model seed " + std::to_string(seed));
    Engine engine(modelScene(seed), refined());
    const Mesh mesh = engine.mesh();
    const BoundCheck check = checkBound(engine, mesh, kTolerance, kSlack, seed);
    EXPECT_EQ(check.over, 0u) << check.first << " (worst " << check.worst << ", capped cells " << mesh.cappedCells
                              << ")";
  }
}

// The check can fail: the fans alone (meshTolerance 0) leave points far off.
TEST(DisplayRefinement, WithoutRefinementTheCheckFails) {
  size_t over = 0;
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    EngineSettings settings;
    settings.meshTolerance = 0;
    Engine engine(makeCubesScene(mixedCubesOptions(seed)), settings);
    const Mesh mesh = engine.mesh();
    EXPECT_EQ(mesh.tolerance, 0.0);
    over += checkBound(engine, mesh, kTolerance, kSlack, seed).over;
  }
  EXPECT_GT(over, 10u);
}

// Random frames: the kept mesh (warm memo) keeps the bound and equals the same engine's mesh
// with its memo dropped, bit for bit.
TEST(DisplayRefinement, EditsKeepTheBoundAndEqualAFreshMesh) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE("cubes seed " + std::to_string(seed));
    Engine engine(makeCubesScene(mixedCubesOptions(seed)), refined());
    engine.mesh();
    std::mt19937_64 rng(seed * 7919);
    int nextNewId = 0;
    for (int f = 0; f < 4; ++f) {
      SCOPED_TRACE("frame " + std::to_string(f));
      const Frame frame = testing::randomFrame(engine, rng, 2, nextNewId);
      engine.apply(frame);
      const Mesh kept = engine.mesh();
      const BoundCheck check = checkBound(engine, kept, kTolerance, kSlack, seed * 31 + uint64_t(f));
      EXPECT_EQ(check.over, 0u) << check.first << " (worst " << check.worst << ")";
      expectSameAsAFreshMesh(engine, kept);
    }
  }
}

// A scripted drag of a tessellated model (slid across the room in steps, turned as it goes): after
// every step the kept mesh (only the cells the step touched refined again) keeps the bound and
// equals the same engine's mesh refined afresh, bit for bit.
TEST(DisplayRefinement, ModelDragKeepsTheBoundAndEqualsAFreshMesh) {
  const Scene scene = modelScene(3);              // a torus knot resting on the floor
  const Object& model = scene.objects().back();  // the generated model comes last
  Engine engine(scene, refined());
  engine.mesh();
  for (int step = 1; step <= 3; ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    Edit move;
    move.op = Edit::Op::Move;
    move.id = model.id;
    move.transform = model.transform;
    move.transform.translate += Vec3(0.07 * step, 0, -0.05 * step);
    move.transform.rotateDeg.y += 5.0 * step;
    engine.apply(Frame{{move}});
    const Mesh kept = engine.mesh();
    EXPECT_EQ(kept.tolerance, kTolerance);
    const BoundCheck check = checkBound(engine, kept, kTolerance, kSlack, 100 + uint64_t(step));
    EXPECT_EQ(check.over, 0u) << check.first << " (worst " << check.worst << ")";
    expectSameAsAFreshMesh(engine, kept);
  }
}

}  // namespace
}  // namespace penumbra
