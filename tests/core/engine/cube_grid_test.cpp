// The overlap cube's grid on scenes with models (core/engine/cube_grid.h): a model that casts
// whole on itself counts as at most kMeshFacesCounted faces, one that reaches the light's
// plane (its faces then pair with each other in the cube) and every model under face-by-face
// casting count in full; the engine's stats report the grid it chose.
#include "core/engine/cube_grid.h"

#include <gtest/gtest.h>

#include "core/engine/engine.h"
#include "core/overlap/overlap_cube.h"
#include "scenegen/model_scene.h"

namespace penumbra {
namespace {

Scene withModelAt(const Scene& scene, const std::string& id, const Vec3& at) {
  std::vector<Object> objects = scene.objects();
  for (Object& object : objects)
    if (object.id == id) object.transform.translate += at;
  return Scene(scene.lights(), scene.materials(), objects, scene.camera());
}

TEST(CubeGrid, AModelCastingWholeOnItselfCountsAsAThousandFaces) {
  const Scene floating = makeModelScene({.kind = ModelKind::Teapot, .triangles = 6000});
  const size_t faces = floating.faces().size();
  const size_t model = floating.facesOfObject(floating.handleOf(*floating.findObject("teapot"))).size();
  ASSERT_GT(model, 6000u);
  const int counted = OverlapCube::gridForFaceCount(faces - model + kMeshFacesCounted);
  EXPECT_EQ(overlapGridFor(floating, 0, true), counted);
  EXPECT_LT(counted, OverlapCube::gridForFaceCount(faces) / 2);
  // Face by face, or reaching the light's plane (1.8 m up: the teapot's top past the ceiling
  // light's 3 m), every face counts.
  EXPECT_EQ(overlapGridFor(floating, 0, false), OverlapCube::gridForFaceCount(faces));
  const Scene atTheLight = withModelAt(floating, "teapot", Vec3(0.0, 1.8, 0.0));
  EXPECT_EQ(overlapGridFor(atTheLight, 0, true), OverlapCube::gridForFaceCount(faces));
  // A model under the threshold counts as itself.
  const Scene small = makeModelScene({.kind = ModelKind::Teapot, .triangles = 1000});
  EXPECT_EQ(overlapGridFor(small, 0, true), OverlapCube::gridForFaceCount(small.faces().size()));
}

TEST(CubeGrid, TheEngineBuildsWithTheGridOfItsScene) {
  const Scene scene = makeModelScene({.kind = ModelKind::TorusKnot, .triangles = 1200});
  EngineSettings settings;
  settings.threads = 1;
  const Engine engine(scene, settings);
  const size_t g = size_t(overlapGridFor(scene, 0, true));
  EXPECT_EQ(engine.stats().tiles, 6 * g * g);
  EXPECT_LT(g, size_t(OverlapCube::gridForFaceCount(scene.faces().size())));
}

}  // namespace
}  // namespace penumbra
