// Per-scene resource limits over real HTTP: a scene or frame that would pass one is answered
// 507 resource_limit naming the limit, and nothing is created or changed.
#include <gtest/gtest.h>

#include <string>

#include "server_fixture.h"

namespace penumbra::server::test {
namespace {

ServerOptions withTreeNodeLimit(size_t nodes) {
  ServerOptions options = RunningServer::loopback();
  options.engine.limits.treeNodes = nodes;
  return options;
}

TEST(ResourceLimit, SceneOverTheTreeNodeLimitIsRefusedAndNothingIsCreated) {
  RunningServer running(withTreeNodeLimit(500));  // cubes15 needs ~3,700 nodes
  TestClient client = running.client();
  const auto res =
      client.Post("/api/scenes?name=big", sceneText("cubes15"), "application/json");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 507) << res->body;
  const json error = bodyJson(res)["error"];
  EXPECT_EQ(error["code"], "resource_limit");
  EXPECT_EQ(error["path"], "limits.tree_nodes");
  const json list = bodyJson(client.Get("/api/scenes"));
  EXPECT_TRUE(list["scenes"].empty()) << list.dump();
}

TEST(ResourceLimit, FrameOverTheLimitIsNotAppliedAndTheSceneKeepsServing) {
  // Find the build's node count with no limit, then allow only a little more: moving a cube
  // to the middle of the floor's light casts new shadows past it.
  size_t built = 0;
  {
    RunningServer probe;
    probe.addBundled("cubes15");
    const json stats = bodyJson(probe.client().Get("/api/scenes/cubes15/stats"))["build"];
    // The limit counts every node, leaves included: a full binary tree per receiver.
    built = 2 * stats["tree_nodes"].get<size_t>() + stats["receivers"].get<size_t>();
  }
  ASSERT_GT(built, 0u);
  RunningServer running(withTreeNodeLimit(built + 1));
  running.addBundled("cubes15");
  TestClient client = running.client();
  const std::string meshBefore = client.Get("/api/scenes/cubes15/mesh?format=bin")->body;
  bool refused = false;
  for (int i = 0; i < 10 && !refused; ++i) {
    const auto res = client.Post("/api/scenes/cubes15/edits",
                                 moveFrame("cube_0", -0.4 + 0.1 * i, 1.2, 0.1 * i).dump(),
                                 "application/json");
    ASSERT_TRUE(res);
    if (res->status == 200) continue;  // this move happened to stay under the limit
    EXPECT_EQ(res->status, 507) << res->body;
    const json error = bodyJson(res)["error"];
    EXPECT_EQ(error["code"], "resource_limit");
    EXPECT_EQ(error["applied"], false);
    EXPECT_EQ(error["limit"], "tree_nodes");
    refused = true;
    // Not applied: the scene is at the version it had, with the mesh that version had.
    const json scene = bodyJson(client.Get("/api/scenes/cubes15"));
    EXPECT_EQ(scene["version"], error["version"]);
    if (i == 0) {
      EXPECT_EQ(client.Get("/api/scenes/cubes15/mesh?format=bin")->body, meshBefore);
    }
  }
  EXPECT_TRUE(refused) << "no move passed " << built + 1 << " tree nodes";
  // The scene keeps serving: a removal shrinks the trees and applies.
  const auto res = client.Post("/api/scenes/cubes15/edits",
                               R"({"edits":[{"op":"remove","id":"cube_1"}]})", "application/json");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200) << res->body;
}

}  // namespace
}  // namespace penumbra::server::test
