// Issue 12's failed frame over real HTTP: a frame that passes the check but fails inside the
// engine is not applied — scene, version and mesh stay as they were and the next edits work.
#include <gtest/gtest.h>

#include <string>

#include "server_fixture.h"

namespace penumbra::server::test {
namespace {

TEST(FailedFrame, ThinCubeMoveIsNotAppliedAndLaterEditsWork) {
  RunningServer running;
  running.addBundled("cubes15");
  httplib::Client client = running.client();
  const std::string base = "/api/scenes/cubes15";
  const auto get = [&](const std::string& path) {
    const auto res = client.Get(path.c_str());
    EXPECT_TRUE(res && res->status == 200) << path;
    return res ? res->body : std::string();
  };
  const auto post = [&](const json& frame) {
    return client.Post((base + "/edits").c_str(), frame.dump(), "application/json");
  };
  const std::string sceneBefore = get(base);
  const std::string meshBefore = get(base + "/mesh?format=bin");

  // cube_8 flattened to 1e-9 m passes checkFrame; the engine used to throw mid-apply and keep
  // the thin cube in its scene while losing it from its trees.
  json thin = json::parse(get(base))["scene"]["objects"];
  json transform;
  for (const json& object : thin)
    if (object["id"] == "cube_8") transform = object["transform"];
  ASSERT_FALSE(transform.is_null());
  transform["scale"][2] = 1e-9;
  const auto failed =
      post({{"edits", json::array({{{"op", "move"}, {"id", "cube_8"}, {"transform", transform}}})}});
  ASSERT_TRUE(failed);
  const json error = json::parse(failed->body)["error"];
  if (failed->status == 422) {
    // Refused up front (a check that knows the geometry is degenerate): nothing applied.
    EXPECT_EQ(error["code"], "invalid_frame") << failed->body;
  } else {
    EXPECT_EQ(failed->status, 500) << failed->body;
    EXPECT_EQ(error["code"], "frame_not_applied") << failed->body;
    EXPECT_EQ(error["applied"], false);
    EXPECT_EQ(error["version"], 0);
    EXPECT_NE(error["message"].get<std::string>().find("not applied"), std::string::npos);
  }
  EXPECT_EQ(get(base), sceneBefore);
  EXPECT_EQ(get(base + "/mesh?format=bin"), meshBefore);

  // The engine still holds every object: removing them and rebuilding work.
  for (const char* id : {"cube_8", "cube_7"}) {
    const auto removed =
        post({{"edits", json::array({{{"op", "remove"}, {"id", id}}})}});
    ASSERT_TRUE(removed);
    EXPECT_EQ(removed->status, 200) << id << ": " << removed->body;
  }
  EXPECT_EQ(json::parse(get(base))["version"], 2);
  const auto rebuilt = client.Post((base + "/rebuild").c_str(), "", "application/json");
  ASSERT_TRUE(rebuilt);
  EXPECT_EQ(rebuilt->status, 200) << rebuilt->body;
  const auto moved = post(moveFrame("cube_6", 0.5, 0.25, 0.5));
  ASSERT_TRUE(moved);
  EXPECT_EQ(moved->status, 200) << moved->body;
  get("/api/scenes");
}

}  // namespace
}  // namespace penumbra::server::test
