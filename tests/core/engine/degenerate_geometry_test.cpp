// Degenerate geometry is built in bounded time and memory or refused with its key
// path, never a runaway (issue 12, item 3): the cases reported against cubes15 as
// regression tests, each run under limits at 4× the unperturbed scene's tree, and
// the resource budget itself (ResourceLimitError, checked during build and apply).
#include <gtest/gtest.h>

#include <string>

#include "core/engine/engine.h"
#include "protocol/scene_json.h"
#include "tests/core/engine/degenerate_fixtures.h"
#include "tests/core/engine/incremental_compare.h"

namespace penumbra {
namespace {

using testing::baselineUsage;
using testing::boundedSettings;
using testing::cubes15Json;

Edit moveEdit(const Scene& scene, const std::string& id, const Transform& transform) {
  (void)scene.findObject(id).value();
  Edit edit;
  edit.op = Edit::Op::Move;
  edit.id = id;
  edit.transform = transform;
  return edit;
}

const Object& objectNamed(const Scene& scene, const std::string& id) {
  return scene.objects()[scene.findObject(id).value()];
}

// Was: the floor's BSP fragment never lay on its own plane (off by 2.5e-7 m, the
// length tolerance is 1.4e-8 m), so every split of it left it in front: without end.
TEST(DegenerateGeometry, FloorCornerRaisedInsideThePlanarityToleranceBuildsBounded) {
  nlohmann::json doc = cubes15Json();
  doc["objects"][0]["vertices"][0][1] = 1e-6;
  const Scene scene = protocol::sceneFromJson(doc);  // accepted, as before
  const Face& floor = scene.faces().front();
  for (const Vec3& p : floor.polygon) EXPECT_LE(std::abs(floor.plane.signedDistance(p)), scene.tolerance().snap());

  const Engine engine(scene, boundedSettings(baselineUsage(), 4));
  EXPECT_LE(engine.resourceUsage().nodes, 4 * baselineUsage().nodes);
  EXPECT_EQ(testing::referenceMismatches(engine, 600, 1), 0u);
}

// Was: passed checkFrame, then "DM-tree receiver must be a convex CCW polygon with
// positive area" mid-apply, the scene holding the thin cube and the engine not.
TEST(DegenerateGeometry, MoveFlatteningACubeIsRefusedBeforeAnythingChanges) {
  Engine engine(protocol::sceneFromJson(cubes15Json()), boundedSettings(baselineUsage(), 4));
  const Transform before = objectNamed(engine.scene(), "cube_8").transform;
  for (double z : {1e-9, 1e-7, 5e-6}) {  // side faces 2z wide: under 1.37e-5 m
    Transform thin = before;
    thin.scale.z = z;
    try {
      engine.apply(Frame{{moveEdit(engine.scene(), "cube_8", thin)}});
      ADD_FAILURE() << "scale z " << z << " accepted";
    } catch (const EditError& error) {
      EXPECT_EQ(error.path(), "transform");
      EXPECT_NE(std::string(error.what()).find("thinner"), std::string::npos) << error.what();
    }
  }
  EXPECT_TRUE(engine.usable());
  EXPECT_EQ(engine.version(), 0u);
  EXPECT_EQ(objectNamed(engine.scene(), "cube_8").transform, before);
  // Side faces 2e-4 m wide: applies, and removing it works after.
  Transform flat = before;
  flat.scale.z = 1e-4;
  engine.apply(Frame{{moveEdit(engine.scene(), "cube_8", flat)}});
  Edit remove;
  remove.op = Edit::Op::Remove;
  remove.id = "cube_8";
  engine.apply(Frame{{remove}});
  EXPECT_EQ(engine.version(), 2u);
  const Engine rebuilt(engine.scene());
  const auto diff = testing::compareEngines(engine, rebuilt, testing::peakIrradiance(rebuilt), 200, 3);
  EXPECT_EQ(diff.errors(), 0u) << diff.firstProblem;
}

TEST(DegenerateGeometry, AddedObjectWithAThinFaceIsRefusedWithTheFacePath) {
  Engine engine(protocol::sceneFromJson(cubes15Json()));
  Edit add;
  add.op = Edit::Op::Add;
  add.object = objectNamed(engine.scene(), "cube_8");
  add.object.id = "sliver";
  add.object.transform.scale.y = 1e-8;
  try {
    engine.apply(Frame{{add}});
    FAIL() << "a 4e-9 m thin cube was accepted";
  } catch (const EditError& error) {
    EXPECT_EQ(error.editIndex(), 0u);
    EXPECT_EQ(error.path().rfind("object.faces[", 0), 0u) << error.path();
  }
  EXPECT_FALSE(engine.scene().findObject("sliver"));
  EXPECT_TRUE(engine.usable());
}

// Was: bad_alloc inside the frame (the same BSP runaway, in FaceOrder::insertFace).
TEST(DegenerateGeometry, CubeWithAVertexOffByOneMicronAppliesBoundedAndEqualsRebuild) {
  Engine engine(protocol::sceneFromJson(cubes15Json()), boundedSettings(baselineUsage(), 4));
  Object cube = objectNamed(engine.scene(), "cube_8");
  cube.vertices[7].x = 0.500001;
  Edit remove, add, addCopy;
  remove.op = Edit::Op::Remove;
  remove.id = "cube_8";
  add.op = Edit::Op::Add;
  add.object = cube;
  addCopy.op = Edit::Op::Add;
  addCopy.object = cube;  // exactly over cube_8: coincident faces too
  addCopy.object.id = "cube_copy";
  engine.apply(Frame{{remove, add}});
  engine.apply(Frame{{addCopy}});
  EXPECT_LE(engine.resourceUsage().nodes, 4 * baselineUsage().nodes);
  const Engine rebuilt(engine.scene());
  const auto diff = testing::compareEngines(engine, rebuilt, testing::peakIrradiance(rebuilt), 200, 5);
  EXPECT_EQ(diff.errors(), 0u) << diff.firstProblem;
  EXPECT_EQ(testing::referenceMismatches(engine, 400, 2), 0u);
}

// The scene validator and the scene agree: what Scene refuses, sceneFromJson refuses
// with the face's key path (the width rule needs the whole scene's size).
TEST(DegenerateGeometry, SceneWithAThinFaceIsRefusedWithItsKeyPath) {
  nlohmann::json doc = cubes15Json();
  doc["objects"][9]["transform"]["scale"][1] = 1e-8;
  try {
    protocol::sceneFromJson(doc);
    FAIL() << "accepted";
  } catch (const protocol::ValidationError& error) {
    EXPECT_EQ(error.path().rfind("objects[9].faces[", 0), 0u) << error.what();
    EXPECT_NE(error.problem().find("thinner"), std::string::npos) << error.what();
  }
}

void expectLimit(const EngineSettings& settings, const std::string& limit) {
  try {
    Engine engine(protocol::sceneFromJson(cubes15Json()), settings);
    ADD_FAILURE() << limit << ": built";
  } catch (const ResourceLimitError& error) {
    EXPECT_EQ(error.limit(), limit);
    EXPECT_GT(error.value(), error.maximum());
  }
}

TEST(ResourceBudget, BuildPastEachLimitThrowsNamingIt) {
  const TreeUsage usage = baselineUsage();
  EngineSettings faces, nodes, vertices, bytes;
  faces.limits.faces = 95;  // cubes15 has 96
  nodes.limits.treeNodes = usage.nodes / 2;
  vertices.limits.vertices = usage.vertices / 2;
  bytes.limits.bytes = usage.bytes / 2;
  expectLimit(faces, "faces");
  expectLimit(nodes, "tree_nodes");
  expectLimit(vertices, "vertices");
  expectLimit(bytes, "bytes");
  // A single tree cannot pass the limit either, even before the totals are checked.
  const Scene scene = protocol::sceneFromJson(cubes15Json());
  EXPECT_THROW(FaceOrder(scene, 0, 8), ResourceLimitError);
}

TEST(ResourceBudget, FrameAddingPastTheFaceLimitIsRefusedAndChangesNothing) {
  EngineSettings settings;
  settings.limits.faces = 96;
  Engine engine(protocol::sceneFromJson(cubes15Json()), settings);
  Edit add;
  add.op = Edit::Op::Add;
  add.object = objectNamed(engine.scene(), "cube_8");
  add.object.id = "one_more";
  add.object.transform.translate.x += 1.5;
  EXPECT_THROW(engine.apply(Frame{{add}}), ResourceLimitError);
  EXPECT_TRUE(engine.usable());
  EXPECT_EQ(engine.version(), 0u);
  EXPECT_EQ(engine.scene().faces().size(), 96u);
  // Remove one, add one: within the limit.
  Edit remove;
  remove.op = Edit::Op::Remove;
  remove.id = "cube_8";
  engine.apply(Frame{{remove, add}});
  EXPECT_EQ(engine.version(), 1u);
}

TEST(ResourceBudget, FrameGrowingTheTreesPastTheLimitThrowsAndLeavesTheEngineMarkedUnusable) {
  const TreeUsage usage = baselineUsage();
  EngineSettings settings;
  settings.limits.treeNodes = usage.nodes + 5;
  Engine engine(protocol::sceneFromJson(cubes15Json()), settings);
  EXPECT_EQ(engine.resourceUsage().nodes, usage.nodes);
  Edit add;  // a new cube: new trees and a new shadow on the floor, far more than 5 nodes
  add.op = Edit::Op::Add;
  add.object = objectNamed(engine.scene(), "cube_8");
  add.object.id = "one_more";
  add.object.transform.translate.x += 1.5;
  try {
    engine.apply(Frame{{add}});
    FAIL() << "frame applied past the node limit";
  } catch (const ResourceLimitError& error) {
    EXPECT_EQ(error.limit(), "tree_nodes");
    EXPECT_EQ(error.maximum(), usage.nodes + 5);
  }
  EXPECT_FALSE(engine.usable());
  EXPECT_THROW(engine.apply(Frame{}), std::logic_error);
}

}  // namespace
}  // namespace penumbra
