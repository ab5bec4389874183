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

#include "bench/lib/sample_points.h"
#include "core/engine/engine.h"
#include "core/raycast/mesh_lookup.h"
#include "core/reference/exact_irradiance.h"
#include "scenegen/cubes_scene.h"
#include "scenegen/model_scene.h"
#include "tests/core/engine/incremental_compare.h"

namespace penumbra {
namespace {

constexpr size_t kPoints = 400;

struct BoundCheck {
  size_t points = 0, over = 0;
  double worst = 0;  // the largest error / (tolerance · local level)
  std::string first;
};

// Each point's error against tolerance × (Σ lights radiance · unshadowed factor), per channel;
// `slack` × that is allowed (the tolerance holds at the refinement's test points, and
// interpolation between them may exceed it by the curvature left).
BoundCheck checkBound(const Engine& engine, const Mesh& mesh, double tolerance, double slack, uint64_t seed) {
  const Scene& scene = engine.scene();
  const MeshLookup lookup(scene, mesh);
  const ExactReference reference(scene);
  std::map<FaceId, uint32_t> faceIndex;
  for (uint32_t i = 0; i < scene.faces().size(); ++i) faceIndex[scene.faces()[i].id] = i;
  BoundCheck out;
  for (const SurfacePoint& point : sampleReceivingPoints(scene, kPoints, seed)) {
    const Vec3 exact = reference.evaluate(point.position, point.normal).irradiance;
    const Vec3 interpolated = lookup.irradiance(faceIndex.at(point.face), point.position).value_or(Vec3(0.0));
    Vec3 level(0.0);
    for (size_t l = 0; l < scene.lights().size(); ++l)
      level += scene.lights()[l].radiance * reference.visibility(point.position, point.normal, l).unoccludedFactor;
    ++out.points;
    for (int c = 0; c < 3; ++c) {
      if (!(level[c] > 0)) continue;
      const double ratio = std::abs(interpolated[c] - exact[c]) / (tolerance * level[c]);
      out.worst = std::max(out.worst, ratio);
      if (ratio > slack) {
        if (out.over++ == 0)
          out.first = "point (" + std::to_string(point.position.x) + ", " + std::to_string(point.position.y) + ", " +
                      std::to_string(point.position.z) + "): mesh " + std::to_string(interpolated[c]) + " exact " +
                      std::to_string(exact[c]) + " level " + std::to_string(level[c]);
        break;
      }
    }
  }
  return out;
}

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

// The engine's kept mesh equals its mesh refined afresh (the memo dropped), bit for bit.
void expectSameAsAFreshMesh(Engine& engine, const Mesh& kept) {
  engine.forgetMeshMemo();
  const Mesh fresh = engine.mesh();
  ASSERT_EQ(kept.receivers.size(), fresh.receivers.size());
  for (size_t i = 0; i < kept.receivers.size(); ++i) {
    EXPECT_EQ(kept.receivers[i].positions, fresh.receivers[i].positions) << "receiver " << i;
    EXPECT_EQ(kept.receivers[i].irradiance, fresh.receivers[i].irradiance) << "receiver " << i;
    EXPECT_EQ(kept.receivers[i].triangles, fresh.receivers[i].triangles) << "receiver " << i;
  }
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
