// Engine::apply with set_material edits: a material's new body (or a new material) changes the
// scene's materials only — the version moves on, no receiver changes, the mesh is bit for bit the
// one before; a frame may add an object in a material it adds; bad frames change nothing.
#include <gtest/gtest.h>

#include <random>

#include "core/engine/engine.h"
#include "scenegen/cubes_scene.h"
#include "tests/core/engine/refused_frame.h"

namespace penumbra {
namespace {

using testing::expectRefusedUnchanged;
using testing::meshText;

Edit setMaterial(const std::string& id, const Vec3& albedo, MaterialType type) {
  Edit edit;
  edit.op = Edit::Op::SetMaterial;
  edit.id = id;
  edit.material.id = id;
  edit.material.albedo = albedo;
  edit.material.type = type;
  return edit;
}

TEST(MaterialEdit, NewBodyChangesTheMaterialOnly) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int round = 0; round < 3; ++round) {
    Engine engine(makeCubesScene(CubesSceneOptions{6, uint64_t(3 + round)}));
    const std::string mesh = meshText(engine);
    const size_t materials = engine.scene().materials().size();
    const Vec3 albedo(unit(rng), unit(rng), unit(rng));
    const FrameResult result =
        engine.apply(Frame{{setMaterial("white", albedo, MaterialType::Conductor)}});
    EXPECT_EQ(result.version, 1u);
    EXPECT_TRUE(result.changedReceivers.empty());
    EXPECT_TRUE(result.removedReceivers.empty());
    EXPECT_FALSE(result.fullRebuild);
    EXPECT_EQ(result.treeRebuilds, 0u);
    EXPECT_EQ(result.verticesRelit, 0u);
    const Scene& scene = engine.scene();
    ASSERT_EQ(scene.materials().size(), materials);  // replaced in place, order kept
    const Material& white = scene.materials()[*scene.findMaterial("white")];
    EXPECT_EQ(white.albedo, albedo);
    EXPECT_EQ(white.type, MaterialType::Conductor);
    EXPECT_TRUE(meshText(engine) == mesh) << "a material changed the mesh";
    EXPECT_NO_THROW(engine.validate());
  }
}

TEST(MaterialEdit, AFrameMayAddAnObjectInAMaterialItAdds) {
  Engine engine(makeCubesScene(CubesSceneOptions{4, 2}));
  const size_t materials = engine.scene().materials().size();
  Object cube = engine.scene().objects()[*engine.scene().findObject("cube_1")];
  Edit remove;
  remove.op = Edit::Op::Remove;
  remove.id = cube.id;
  cube.material = "paint";
  Edit add;
  add.op = Edit::Op::Add;
  add.id = cube.id;
  add.object = cube;
  engine.apply(Frame{{setMaterial("paint", Vec3(0.9, 0.1, 0.1), MaterialType::Diffuse), remove, add}});
  const Scene& scene = engine.scene();
  ASSERT_EQ(scene.materials().size(), materials + 1);
  EXPECT_EQ(scene.materials().back().id, "paint");
  EXPECT_EQ(scene.objects()[*scene.findObject("cube_1")].material, "paint");
  EXPECT_NO_THROW(engine.validate());

  // Without the set_material first, the same add is refused and nothing changes.
  cube.id = "cube_new";
  cube.material = "varnish";
  add.id = cube.id;
  add.object = cube;
  expectRefusedUnchanged(engine, Frame{{add, setMaterial("varnish", Vec3(0.5), MaterialType::Diffuse)}}, 0,
                         "object");
  expectRefusedUnchanged(engine, Frame{{setMaterial("", Vec3(0.5), MaterialType::Diffuse)}}, 0, "id");
}

}  // namespace
}  // namespace penumbra
