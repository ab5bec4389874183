// Engine::apply with add_light and remove_light: each is a counted full rebuild that gives
// exactly what a fresh build of the edited scene gives, adding then removing a light gives
// back the mesh bit for bit, and bad edits are refused with the key path, changing nothing.
#include <gtest/gtest.h>

#include <cmath>

#include "core/engine/engine.h"
#include "protocol/mesh_json.h"
#include "protocol/scene_json.h"
#include "scenegen/cubes_scene.h"
#include "tests/core/engine/incremental_compare.h"
#include "tests/core/engine/refused_frame.h"

namespace penumbra {
namespace {

using testing::moveEditBy;
using testing::scaledMoved;
using testing::expectRefusedUnchanged;
using testing::meshText;


Edit addLight(const std::string& id, const Polygon3& polygon, const Vec3& radiance) {
  Edit edit;
  edit.op = Edit::Op::AddLight;
  edit.light = Light{id, polygon, radiance};
  edit.id = id;
  return edit;
}

Edit removeLight(const std::string& id) {
  Edit edit;
  edit.op = Edit::Op::RemoveLight;
  edit.id = id;
  return edit;
}

// Equal to a rebuild of the scene it holds (DESIGN.md invariant 3); right after a full
// rebuild (`fresh`) the mesh is that of a fresh build bit for bit.
void expectEqualsRebuild(Engine& engine, uint64_t seed, bool fresh) {
  EXPECT_NO_THROW(engine.validate());
  Engine rebuilt(engine.scene());
  if (fresh) {
    EXPECT_TRUE(meshText(engine) == meshText(rebuilt)) << "mesh differs from a fresh build's";
  }
  const testing::EngineDiff diff =
      testing::compareEngines(engine, rebuilt, testing::peakIrradiance(rebuilt), 100, seed);
  EXPECT_EQ(diff.errors(), 0u) << diff.firstProblem;
}

TEST(LightCountEdit, AddedLightEqualsAFreshBuildAndRemovingItRestoresTheMesh) {
  Engine engine(makeCubesScene(CubesSceneOptions{6, 3}));
  engine.apply(Frame{{moveEditBy(engine, "cube_1", Vec3(0.05, 0, 0))}});  // not a fresh build
  Engine fresh(engine.scene());
  const std::string before = meshText(fresh);  // a full rebuild's mesh of this scene
  const Light first = engine.scene().lights()[0];
  const Polygon3 polygon = scaledMoved(first.polygon, 0.5, Vec3(0.8, 0, -0.6));

  const FrameResult added = engine.apply(Frame{{addLight("lamp2", polygon, Vec3(4, 5, 6))}});
  EXPECT_TRUE(added.fullRebuild);
  EXPECT_EQ(added.treeRebuilds, engine.receivers().size());
  ASSERT_EQ(engine.scene().lights().size(), 2u);
  EXPECT_EQ(engine.scene().lights()[1].id, "lamp2");  // a new light comes last
  EXPECT_EQ(engine.scene().lights()[1].polygon, polygon);
  EXPECT_TRUE(meshText(engine) != before);
  expectEqualsRebuild(engine, 1, true);

  // Object frames after it run incrementally with both lights.
  const FrameResult moved = engine.apply(Frame{{moveEditBy(engine, "cube_2", Vec3(-0.1, 0, 0.05))}});
  EXPECT_FALSE(moved.fullRebuild);
  expectEqualsRebuild(engine, 2, false);
  Edit back = moveEditBy(engine, "cube_2", Vec3(0.0));
  back.transform = fresh.scene().objects()[*fresh.scene().findObject("cube_2")].transform;
  engine.apply(Frame{{back}});

  const FrameResult removed = engine.apply(Frame{{removeLight("lamp2")}});
  EXPECT_TRUE(removed.fullRebuild);
  ASSERT_EQ(engine.scene().lights().size(), 1u);
  EXPECT_TRUE(meshText(engine) == before) << "not the mesh before the light came";
}

// Removing one of two lights: the faces only it reached are reported removed receivers.
TEST(LightCountEdit, RemovedLightEqualsAFreshBuild) {
  Engine engine(makeCubesScene(mixedCubesOptions(17)));  // two tilted lights
  ASSERT_EQ(engine.scene().lights().size(), 2u);
  const Light second = engine.scene().lights()[1];
  const FrameResult result =
      engine.apply(Frame{{moveEditBy(engine, "cube_0", Vec3(0.03, 0, 0)), removeLight("light")}});
  EXPECT_TRUE(result.fullRebuild);
  ASSERT_EQ(engine.scene().lights().size(), 1u);
  EXPECT_EQ(engine.scene().lights()[0].id, second.id);
  expectEqualsRebuild(engine, 3, true);
  for (FaceId face : result.removedReceivers) EXPECT_EQ(engine.receiver(face), nullptr);

  // Added back (now last): the same lights as a set, values equal a rebuild.
  Engine twoLights(makeCubesScene(mixedCubesOptions(17)));
  const Light first = twoLights.scene().lights()[0];
  engine.apply(Frame{{addLight(first.id, first.polygon, first.radiance)}});
  EXPECT_EQ(engine.scene().lights()[1].id, "light");
  expectEqualsRebuild(engine, 4, true);
}

TEST(LightCountEdit, BadAddAndRemoveChangeNothing) {
  Engine engine(makeCubesScene(CubesSceneOptions{4, 2}));
  engine.apply(Frame{{moveEditBy(engine, "cube_0", Vec3(0.05, 0, 0))}});
  const Light light = engine.scene().lights()[0];
  const Polygon3 small = scaledMoved(light.polygon, 0.5, Vec3(0.5, 0, 0));
  const Edit move = moveEditBy(engine, "cube_0", Vec3(0.02, 0, 0));

  // remove_light: an unknown id, an object's id, the last light (also after a valid edit).
  expectRefusedUnchanged(engine, Frame{{move, removeLight("lamp")}}, 1, "id");
  expectRefusedUnchanged(engine, Frame{{removeLight("cube_0")}}, 0, "id");
  expectRefusedUnchanged(engine, Frame{{removeLight("light")}}, 0, "id");
  expectRefusedUnchanged(
      engine, Frame{{move, removeLight("light"), addLight("b", small, Vec3(1.0))}}, 1, "id");
  // Removed twice in one frame (the second no longer exists).
  expectRefusedUnchanged(
      engine, Frame{{addLight("b", small, Vec3(1.0)), removeLight("light"), removeLight("light")}},
      2, "id");

  // add_light: a duplicate id (also one the frame added), each rule of a scene's lights.
  expectRefusedUnchanged(engine, Frame{{addLight("light", small, Vec3(1.0))}}, 0, "light.id");
  expectRefusedUnchanged(engine,
                         Frame{{addLight("b", small, Vec3(1.0)), addLight("b", small, Vec3(1.0))}},
                         1, "light.id");
  Polygon3 bent = small;
  bent[0].y -= 0.3;
  expectRefusedUnchanged(engine, Frame{{move, addLight("b", bent, Vec3(1.0))}}, 1, "light.polygon");
  Polygon3 twoPoints{small[0], small[1]};
  expectRefusedUnchanged(engine, Frame{{addLight("b", twoPoints, Vec3(1.0))}}, 0, "light.polygon");
  const Vec3 c = small[0];
  const Polygon3 sliver{c, c + Vec3(1, 0, 0), c + Vec3(1, 0, 1e-9), c + Vec3(0, 0, 1e-9)};
  expectRefusedUnchanged(engine, Frame{{addLight("b", sliver, Vec3(1.0))}}, 0, "light.polygon");
  Polygon3 nan = small;
  nan[2].x = NAN;
  expectRefusedUnchanged(engine, Frame{{addLight("b", nan, Vec3(1.0))}}, 0, "light.polygon");
  expectRefusedUnchanged(engine,
                         Frame{{addLight("b", scaledMoved(small, 1, Vec3(0, 50, 0)), Vec3(1.0))}},
                         0, "light.polygon[0]");
  expectRefusedUnchanged(engine, Frame{{addLight("b", small, Vec3(1, -1, 1))}}, 0,
                         "light.radiance");
  expectRefusedUnchanged(engine, Frame{{addLight("b", small, Vec3(1, NAN, 1))}}, 0,
                         "light.radiance");
  // A light the frame added and removed again: the original is the last one again.
  expectRefusedUnchanged(
      engine, Frame{{addLight("b", small, Vec3(1.0)), removeLight("b"), removeLight("light")}}, 2,
      "id");

  // Adding then removing the first light in one frame: the frame sees the lights as its
  // earlier edits leave them.
  const FrameResult swapped =
      engine.apply(Frame{{addLight("b", small, Vec3(2.0)), removeLight("light")}});
  EXPECT_TRUE(swapped.fullRebuild);
  ASSERT_EQ(engine.scene().lights().size(), 1u);
  EXPECT_EQ(engine.scene().lights()[0].id, "b");
  expectEqualsRebuild(engine, 5, true);
}

TEST(LightCountEdit, SceneAddAndRemoveLightCheck) {
  Scene scene = makeCubesScene(CubesSceneOptions{2, 1});
  const Light light = scene.lights()[0];
  EXPECT_THROW(scene.addLight(light), std::invalid_argument);  // duplicate id
  EXPECT_THROW(scene.removeLight(0), std::invalid_argument);   // the last light
  EXPECT_THROW(scene.removeLight(3), std::invalid_argument);
  Light negative{"n", light.polygon, Vec3(-1.0)};
  EXPECT_THROW(scene.addLight(negative), std::invalid_argument);
  ASSERT_EQ(scene.lights().size(), 1u);
  const Bounds bounds = scene.bounds();
  scene.addLight(Light{"two", scaledMoved(light.polygon, 0.5, Vec3(0.3, 0, 0)), Vec3(1.0)});
  scene.removeLight(0);
  ASSERT_EQ(scene.lights().size(), 1u);
  EXPECT_EQ(scene.lights()[0].id, "two");
  EXPECT_EQ(scene.bounds().min, bounds.min);  // bounds stay as constructed
  EXPECT_EQ(scene.bounds().max, bounds.max);
}

}  // namespace
}  // namespace penumbra
