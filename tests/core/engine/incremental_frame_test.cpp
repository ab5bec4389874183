// Engine::apply on hand-made frames: invalid frames change nothing (version, scene
// and mesh byte-identical), a move relights only near the moved object, receivers
// of removed objects are reported, undoing a move restores the values, and edits of
// one id within a frame follow each other.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/engine/engine.h"
#include "protocol/mesh_json.h"
#include "protocol/scene_json.h"
#include "scenegen/cubes_scene.h"
#include "tests/core/engine/incremental_compare.h"
#include "tests/core/engine/refused_frame.h"

namespace penumbra {
namespace {

using testing::moveEditBy;
using testing::expectRefusedUnchanged;
using testing::sceneText;


TEST(IncrementalFrame, InvalidFramesChangeNothing) {
  Engine engine(makeCubesScene(mixedCubesOptions(4)));
  engine.apply(Frame{{moveEditBy(engine, "cube_0", Vec3(0.1, 0, 0))}});  // a state that is not a fresh build

  Edit unknown;
  unknown.op = Edit::Op::Remove;
  unknown.id = "no_such_object";
  expectRefusedUnchanged(engine, Frame{{moveEditBy(engine, "cube_0", Vec3(0.05, 0, 0)), unknown}}, 1, "id");

  Edit duplicate;
  duplicate.op = Edit::Op::Add;
  duplicate.object = engine.scene().objects()[*engine.scene().findObject("cube_1")];
  expectRefusedUnchanged(engine, Frame{{moveEditBy(engine, "cube_0", Vec3(0.05, 0, 0)), duplicate}}, 1, "object.id");

  Edit zeroScale = moveEditBy(engine, "cube_1", Vec3(0.0));
  zeroScale.transform.scale = Vec3(0.0);
  expectRefusedUnchanged(engine, Frame{{zeroScale}}, 0, "transform");

  // Far outside the room: the overlap cubes could not find its shadows.
  expectRefusedUnchanged(engine, Frame{{moveEditBy(engine, "cube_0", Vec3(100, 0, 0))}}, 0, "transform");
}

TEST(IncrementalFrame, MoveRelightsLocallyAndUndoRestores) {
  Engine many(makeCubesScene(CubesSceneOptions{12, 5}));
  size_t total = 0;
  for (const auto& r : many.receivers()) total += r.tree.vertexCount();

  const FrameResult moved = many.apply(Frame{{moveEditBy(many, "cube_3", Vec3(0.02, 0, 0.01))}});
  EXPECT_EQ(moved.version, 1u);
  EXPECT_EQ(moved.treeRebuilds, 0u);
  EXPECT_GT(moved.verticesRelit, 0u);
  EXPECT_LT(moved.verticesRelit, total / 2) << "a small move relit most of the scene";
  EXPECT_LE(moved.verticesChanged, moved.verticesRelit);
  EXPECT_TRUE(moved.removedReceivers.empty());
  // The moved cube's own receiving faces are among the changed ones.
  const uint32_t handle = many.scene().handleOf(*many.scene().findObject("cube_3"));
  EXPECT_TRUE(std::any_of(moved.changedReceivers.begin(), moved.changedReceivers.end(),
                          [&](FaceId f) { return f.object == handle; }));

  const FrameResult back = many.apply(Frame{{moveEditBy(many, "cube_3", Vec3(-0.02, 0, -0.01))}});
  EXPECT_EQ(back.version, 2u);
  const Engine rebuilt(many.scene());
  const testing::EngineDiff diff = testing::compareEngines(many, rebuilt, testing::peakIrradiance(rebuilt), 100, 1);
  EXPECT_EQ(diff.errors(), 0u) << diff.firstProblem;
}

TEST(IncrementalFrame, RemoveReportsReceiversAndAddBringsThemBack) {
  Engine engine(makeCubesScene(CubesSceneOptions{6, 9}));
  const uint32_t handle = engine.scene().handleOf(*engine.scene().findObject("cube_2"));
  const Object cube = engine.scene().objects()[*engine.scene().findObject("cube_2")];
  Edit remove;
  remove.op = Edit::Op::Remove;
  remove.id = "cube_2";
  const FrameResult removed = engine.apply(Frame{{remove}});
  EXPECT_FALSE(removed.removedReceivers.empty());
  for (FaceId f : removed.removedReceivers) EXPECT_EQ(f.object, handle);
  for (const auto& r : engine.receivers()) EXPECT_NE(r.face.object, handle);
  EXPECT_TRUE(engine.castOn(FaceId{handle, 0}).empty());

  Edit add;
  add.op = Edit::Op::Add;
  add.object = cube;
  const FrameResult added = engine.apply(Frame{{add}});
  EXPECT_GT(added.verticesCreated, 0u);
  const Engine rebuilt(engine.scene());
  const testing::EngineDiff diff = testing::compareEngines(engine, rebuilt, testing::peakIrradiance(rebuilt), 100, 2);
  EXPECT_EQ(diff.errors(), 0u) << diff.firstProblem;
  EXPECT_NO_THROW(engine.validate());
}

// Frames naming one id several times: the check follows the earlier edits of the
// frame (sceneAfter gives the scene apply makes), and the result equals a rebuild.
TEST(IncrementalFrame, EditsOfOneIdWithinAFrameFollowEachOther) {
  Engine engine(makeCubesScene(CubesSceneOptions{6, 9}));
  const Object cube = engine.scene().objects()[*engine.scene().findObject("cube_2")];
  Edit remove;
  remove.op = Edit::Op::Remove;
  remove.id = "cube_2";
  Edit addBack;
  addBack.op = Edit::Op::Add;
  addBack.object = cube;
  addBack.object.transform.translate += Vec3(0.05, 0, 0.03);
  Edit addNew;
  addNew.op = Edit::Op::Add;
  addNew.object = cube;
  addNew.object.id = "cube_new";
  addNew.object.transform.translate += Vec3(-0.3, 0, 0.2);
  Edit moveNew;
  moveNew.op = Edit::Op::Move;
  moveNew.id = "cube_new";
  moveNew.transform = addNew.object.transform;
  moveNew.transform.translate += Vec3(0.04, 0, 0);
  Edit removeNew;
  removeNew.op = Edit::Op::Remove;
  removeNew.id = "cube_new";

  const std::vector<Frame> frames = {
      Frame{{remove, addBack}},                                                        // same id, new object
      Frame{{addNew, moveNew}},                                                        // added, then moved
      Frame{{moveEditBy(engine, "cube_1", Vec3(0.03, 0, 0)), moveEditBy(engine, "cube_1", Vec3(0, 0, 0.03))}},
      Frame{{removeNew, addNew, removeNew}},                                           // net: gone
  };
  for (size_t f = 0; f < frames.size(); ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    const std::string expected = protocol::sceneToJson(engine.sceneAfter(frames[f])).dump();
    engine.apply(frames[f]);
    EXPECT_EQ(sceneText(engine), expected);
    EXPECT_NO_THROW(engine.validate());
    const Engine rebuilt(engine.scene());
    const testing::EngineDiff diff = testing::compareEngines(engine, rebuilt, testing::peakIrradiance(rebuilt), 100, f);
    EXPECT_EQ(diff.errors(), 0u) << diff.firstProblem;
  }
  EXPECT_FALSE(engine.scene().findObject("cube_new"));
  // A later edit of the frame names an id an earlier one removed: refused, nothing changed.
  expectRefusedUnchanged(engine, Frame{{remove, moveEditBy(engine, "cube_2", Vec3(0.01, 0, 0))}}, 1, "id");
}

}  // namespace
}  // namespace penumbra
