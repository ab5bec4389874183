// Bad requests over real HTTP: every one gets a 4xx JSON error naming the key path,
// and the scene (version, mesh) is left exactly as it was.
#include <gtest/gtest.h>

#include "server_fixture.h"

namespace penumbra::server::test {
namespace {

void expectError(const Reply& res, int status, const std::string& code,
                 const std::string& path) {
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, status) << res->body;
  EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
  const json body = json::parse(res->body);
  ASSERT_TRUE(body.contains("error")) << res->body;
  EXPECT_EQ(body["error"]["code"], code) << res->body;
  EXPECT_EQ(body["error"]["path"], path) << res->body;
  EXPECT_FALSE(body["error"]["message"].get<std::string>().empty());
}

class ServerErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    id_ = running_.addBundled("cornell");
    base_ = "/api/scenes/" + id_;
    before_ = client_.Get((base_ + "/mesh").c_str())->body;
  }
  // The scene is still at version 0 with the very same mesh.
  void expectUnchanged() {
    EXPECT_EQ(bodyJson(client_.Get(base_.c_str()))["version"], 0);
    EXPECT_EQ(client_.Get((base_ + "/mesh").c_str())->body, before_);
  }
  Reply postEdits(const std::string& body) {
    return client_.Post((base_ + "/edits").c_str(), body, "application/json");
  }

  RunningServer running_;
  TestClient client_ = running_.client();
  std::string id_, base_, before_;
};

TEST_F(ServerErrors, MalformedJsonIs400) {
  expectError(postEdits("{\"edits\": [ {\"op\": \"move\", "), 400, "malformed_json", "(json)");
  expectError(postEdits(""), 400, "malformed_json", "(json)");
  expectError(client_.Post("/api/scenes", "[1, 2", "application/json"), 400, "malformed_json",
              "(json)");
  expectUnchanged();
}

// Fuzzing found it (tests/fuzz/crashes/http_request/url-invalid-utf8.http): the 404 body
// names the decoded path, and dumping invalid UTF-8 threw outside any handler.
TEST_F(ServerErrors, InvalidUtf8InTheUrlIs404AndTheServerLives) {
  for (const char* path : {"/%ff", "/%c3%28?name=%ff", "/api/%fe%ff"}) {
    expectError(client_.Get(path), 404, "not_found", "(url)");
  }
  EXPECT_EQ(client_.Get("/api/health")->status, 200);
  expectUnchanged();
}

TEST_F(ServerErrors, UnknownSceneIs404) {
  expectError(client_.Get("/api/scenes/nope"), 404, "not_found", "id");
  expectError(client_.Get("/api/scenes/nope/mesh"), 404, "not_found", "id");
  expectError(client_.Post("/api/scenes/nope/edits", moveFrame("tall_block", 1, 0, 1).dump(),
                           "application/json"),
              404, "not_found", "id");
  expectError(client_.Get("/api/no/such/route"), 404, "not_found", "(url)");
}

TEST_F(ServerErrors, UnknownObjectInFrameIs422AndChangesNothing) {
  // The second edit names an object that does not exist: the first one must not apply either.
  const json frame = {{"edits", json::array({moveFrame("tall_block", 3.0, 0, 3.0)["edits"][0],
                                             moveFrame("ghost", 1, 0, 1)["edits"][0]})}};
  const auto res = postEdits(frame.dump());
  expectError(res, 422, "invalid_frame", "edits[1].id");
  EXPECT_EQ(json::parse(res->body)["error"]["edit"], 1);
  expectUnchanged();
}

TEST_F(ServerErrors, InvalidFrameShapesAre422WithTheirPath) {
  json zeroScale = moveFrame("tall_block", 3, 0, 3);
  zeroScale["edits"][0]["transform"]["scale"] = {1, 0, 1};
  const auto res = postEdits(zeroScale.dump());
  ASSERT_EQ(res->status, 422);
  EXPECT_EQ(json::parse(res->body)["error"]["code"], "invalid_frame");
  EXPECT_EQ(json::parse(res->body)["error"]["path"].get<std::string>().rfind(
                "edits[0].transform.scale", 0),
            0u)
      << res->body;
  EXPECT_EQ(json::parse(res->body)["error"]["edit"], 0);
  expectError(postEdits(R"({"edits": [{"op": "spin", "id": "tall_block"}]})"), 422, "invalid_frame",
              "edits[0].op");
  expectError(postEdits(R"({"edits": 3})"), 422, "invalid_frame", "edits");
  const json addDuplicate = {
      {"edits", json::array({{{"op", "add"},
                              {"object", json::parse(sceneText("cornell"))["objects"][6]}}})}};
  expectError(postEdits(addDuplicate.dump()), 422, "invalid_frame", "edits[0].object.id");
  expectUnchanged();
}

TEST_F(ServerErrors, InvalidSceneIs422WithTheKeyPath) {
  json scene = json::parse(sceneText("cornell"));
  scene["objects"][3]["faces"][0] = {0, 1, 99};
  expectError(client_.Post("/api/scenes", scene.dump(), "application/json"), 422, "invalid_scene",
              "objects[3].faces[0][2]");
  EXPECT_EQ(bodyJson(client_.Get("/api/scenes"))["scenes"].size(), 1u);
}

TEST_F(ServerErrors, OversizedBodyIs413) {
  const std::string huge(kMaxBodyBytes + 1, ' ');
  expectError(postEdits(huge), 413, "payload_too_large", "(body)");
  expectUnchanged();
}

TEST_F(ServerErrors, BadQueryParametersAre400) {
  expectError(client_.Get((base_ + "/image?width=0&height=64").c_str()), 400, "bad_parameter",
              "query.width");
  expectError(client_.Get((base_ + "/image?width=64&height=5000").c_str()), 400, "bad_parameter",
              "query.height");
  expectError(client_.Get((base_ + "/image?width=64").c_str()), 400, "bad_parameter",
              "query.height");
  expectError(client_.Get((base_ + "/image?width=abc&height=64").c_str()), 400, "bad_parameter",
              "query.width");
  expectError(client_.Get((base_ + "/image?width=64&height=64&position=1,2").c_str()), 400,
              "bad_parameter", "query.position");
  expectError(client_.Get((base_ + "/mesh?since=5").c_str()), 400, "bad_parameter", "query.since");
  expectError(client_.Get((base_ + "/mesh?since=-1").c_str()), 400, "bad_parameter", "query.since");
  expectError(client_.Get((base_ + "/mesh?format=obj").c_str()), 400, "bad_parameter",
              "query.format");
  expectUnchanged();
}

}  // namespace
}  // namespace penumbra::server::test
