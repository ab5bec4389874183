// Non-convex meshes cast whole from their silhouettes (issue 35): a bumpy sphere, a tilted
// torus and an open bowl floating in the dense room match the exact reference at every DM
// vertex, list the object once per cell instead of face by face, and a frame moving one
// equals a rebuild.
#include <gtest/gtest.h>

#include <cstdio>

#include "bench/lib/dense_scene.h"
#include "bench/lib/scene_parts.h"
#include "core/engine/engine.h"
#include "core/scene/mesh_topology.h"
#include "tests/core/engine/incremental_compare.h"
#include "tests/core/engine/reference_check.h"
#include "tests/core/illum/random_meshes.h"

namespace penumbra {
namespace {

Scene roomWith(std::vector<Object> models) {
  std::vector<Light> lights{squareCeilingLight("light", Vec3(0.2, kDenseLightY, -0.1), kDenseLightSide, 0, Vec3(1, 0, 0))};
  std::vector<Object> objects = roomObjects(kDenseHalfSide, kDenseHalfSide, kDenseHeight);
  for (Object& m : models) objects.push_back(std::move(m));
  return Scene(std::move(lights), {{"white", Vec3(0.8)}}, std::move(objects));
}

void expectExact(Engine& engine, const std::string& label) {
  const testing::ReferenceCheck c = testing::checkAgainstReference(engine, label);
  std::printf("%s: %zu vertices, %zu value errors, %zu class errors\n", label.c_str(), c.vertices, c.valueErrors,
              c.classErrors);
  EXPECT_GT(c.vertices, 1000u) << label;
  EXPECT_EQ(c.valueErrors, 0u) << label;
  EXPECT_EQ(c.classErrors, 0u) << label;
}

// Whether some receiver took the object's shadow whole.
bool castWhole(const Engine& engine, uint32_t handle) {
  return !engine.castOn(wholeObject(handle)).empty();
}

TEST(MeshEngine, FloatingNonConvexMeshesMatchReference) {
  const std::vector<std::pair<const char*, Object>> models = {
      {"bumpy sphere", test::bumpySphere("m", {0.3, 1.1, -0.2}, 0.4, 8, 0.3, 5)},
      {"torus", test::torus("m", {0.1, 1.2, 0.2}, 0.45, 0.14, 16, 8, 0.6)},
      {"open bowl", test::bowl("m", {-0.2, 1.3, 0.1}, 0.45, 10, 0.2, 2)},
  };
  for (const auto& [name, model] : models) {
    Engine engine(roomWith({model}));
    const uint32_t handle = engine.scene().handleOf(*engine.scene().findObject("m"));
    ASSERT_NE(engine.scene().meshTopology(handle), nullptr);
    EXPECT_TRUE(castWhole(engine, handle)) << name;
    expectExact(engine, name);
  }
}

TEST(MeshEngine, MovesEqualRebuild) {
  Engine engine(roomWith({test::torus("m", {0.1, 1.2, 0.2}, 0.45, 0.14, 16, 8, 0.6),
                          test::bumpySphere("s", {-1.0, 0.8, 0.6}, 0.3, 6, 0.3, 9)}));
  const Vec3 steps[] = {{0.05, 0.0, 0.02}, {0.2, -0.1, 0.0}, {-0.9, 0.1, 0.5}};
  int f = 0;
  for (const Vec3& step : steps) {
    Edit move;
    move.op = Edit::Op::Move;
    move.id = "m";
    move.transform.translate = step;
    move.transform.rotateDeg = Vec3(5.0 * f, 10.0 * f, 0);
    const FrameResult result = engine.apply(Frame{{move}});
    EXPECT_FALSE(result.fullRebuild);
    engine.validate();
    Engine rebuilt(engine.scene());
    const testing::EngineDiff diff =
        testing::compareEngines(engine, rebuilt, testing::peakIrradiance(rebuilt), 200, uint64_t(f));
    EXPECT_EQ(diff.errors(), 0u) << "frame " << f << ": " << diff.firstProblem;
    ++f;
  }
  expectExact(engine, "torus after moves");
}

}  // namespace
}  // namespace penumbra
