// A frame's light work is estimated before it starts (server/frame_cost.h) and a frame past the
// limit is refused with 422 frame_too_costly at `edits`, naming the estimate and the limit, the
// scene unchanged; below it the frame applies. Seeded frames of random light and face additions:
// refused exactly when light changes × lights × faces + faces added × lights is past the limit.
#include "server/frame_cost.h"

#include <gtest/gtest.h>

#include <random>

#include "protocol/edits_json.h"
#include "server/api_errors.h"
#include "server_fixture.h"
#include "tiny_scene.h"

namespace penumbra::server::test {
namespace {

json light(const std::string& id, double x) {
  return {
      {"op", "add_light"},
      {"light",
       {{"id", id},
        {"radiance", {5, 5, 5}},
        {"polygon",
         {{x - 0.1, 2.5, -0.1}, {x + 0.1, 2.5, -0.1}, {x + 0.1, 2.5, 0.1}, {x - 0.1, 2.5, 0.1}}}}}};
}

json panel(const std::string& id, int faces) {  // a strip of `faces` quads high above the box
  json vertices = json::array(), quads = json::array();
  for (int i = 0; i <= faces; ++i) {
    vertices.push_back({-2.0 + 0.01 * i, 2.0, -2.8});
    vertices.push_back({-2.0 + 0.01 * i, 2.0, -2.7});
  }
  for (int i = 0; i < faces; ++i) quads.push_back({2 * i, 2 * i + 1, 2 * i + 3, 2 * i + 2});
  return {{"op", "add"}, {"object", {{"id", id}, {"vertices", vertices}, {"faces", quads}}}};
}

TEST(FrameCost, AFramePastTheLimitIs422NamingItAndChangesNothing) {
  // The tiny scene: 7 faces, 1 light. Adding one light: 1 × 2 × 7 = 14.
  ServerOptions options = RunningServer::loopback();
  options.maxFrameWork = 14;
  RunningServer running(options);
  running.server().addScene(protocol::sceneFromJson(tinyScene()), "tiny.scene.json", "tiny");
  auto client = running.client();
  const auto two = postJson(client, "/api/scenes/tiny/edits",
                            {{"edits", {light("a", -1), light("b", 1)}}});  // 2 × 3 × 7 = 42
  ASSERT_TRUE(two);
  EXPECT_EQ(two->status, 422) << two->body;
  const json error = bodyJson(two)["error"];
  EXPECT_EQ(error["code"], "frame_too_costly");
  EXPECT_EQ(error["path"], "edits");
  const std::string message = error["message"];
  EXPECT_NE(message.find("2 light changes × 3 lights × 7 faces"), std::string::npos) << message;
  EXPECT_NE(message.find("= 42"), std::string::npos) << message;
  EXPECT_NE(message.find("limit of 14"), std::string::npos) << message;
  EXPECT_EQ(bodyJson(client.Get("/api/scenes/tiny"))["version"], 0);
  const auto one = postJson(client, "/api/scenes/tiny/edits", {{"edits", {light("a", -1)}}});
  ASSERT_TRUE(one);
  EXPECT_EQ(one->status, 200) << one->body;
}

TEST(FrameCost, EstimateMatchesTheFormulaOnSeededFrames) {
  const Scene scene = protocol::sceneFromJson(tinyScene());
  std::mt19937 random(20261128);
  for (int trial = 0; trial < 200; ++trial) {
    json edits = json::array();
    uint64_t lights = 1, faces = 7, changes = 0, added = 0;
    const int n = int(random() % 6);
    for (int i = 0; i < n; ++i) {
      if (random() % 2) {
        edits.push_back(light("l" + std::to_string(i), -2 + 0.5 * i));
        ++lights;
        ++changes;
      } else {
        const int f = 1 + int(random() % 20);
        edits.push_back(panel("p" + std::to_string(i), f));
        faces += uint64_t(f);
        added += uint64_t(f);
      }
    }
    if (random() % 3 == 0) {  // reshape the lamp
      edits.push_back(
          {{"op", "set_light"},
           {"id", "lamp"},
           {"polygon", {{-0.4, 2.9, -0.4}, {0.4, 2.9, -0.4}, {0.4, 2.9, 0.4}, {-0.4, 2.9, 0.4}}}});
      ++changes;
    }
    if (edits.empty()) continue;
    const Frame frame = protocol::frameFromJson({{"edits", edits}});
    const FrameCost cost = estimateFrameCost(scene, frame);
    const uint64_t expected = changes * lights * faces + added * lights;
    ASSERT_EQ(cost.work(), expected) << edits.dump();
    const uint64_t limit = uint64_t(random() % 400);
    bool refused = false;
    try {
      refuseCostlyFrame(cost, limit);
    } catch (const ApiError& error) {
      refused = true;
      EXPECT_EQ(error.status(), 422);
      EXPECT_EQ(error.path(), "edits");
    }
    EXPECT_EQ(refused, expected > limit) << expected << " vs " << limit;
  }
}

}  // namespace
}  // namespace penumbra::server::test
