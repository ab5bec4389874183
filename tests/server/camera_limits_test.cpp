// Issue 36, item 1: every number at the boundary is checked by class. The image route's camera
// parameters and an uploaded scene's camera go through core's validateCamera (extreme doubles
// answer 400/422 naming the key, never a crash: Embree's ray assertion used to abort the server),
// a refused upload leaves nothing (not served, not journaled), and the other numeric inputs
// (coordinates, transforms, radiance, GI keys, samples, image size) have their bounds.
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "server_fixture.h"
#include "temp_data_dir.h"
#include "tiny_scene.h"

namespace penumbra::server::test {
namespace {

std::string addTinyScene(TestClient& client, const json& scene = tinyScene()) {
  const auto res = postJson(client, "/api/scenes?name=tiny", scene);
  EXPECT_EQ(res->status, 201) << res->body;
  return bodyJson(res)["id"];
}

size_t sceneCount(TestClient& client) {
  return bodyJson(client.Get("/api/scenes"))["scenes"].size();
}

// Extreme spellings of doubles: signed zeros, denormals, the ends of the range, non-numbers
// (refused by the query parser), huge and tiny values, and a few ordinary ones.
const std::vector<std::string> kSpellings = {"0",
                                             "-0",
                                             "4.9e-324",
                                             "2.2250738585072014e-308",
                                             "1e-300",
                                             "-1e-300",
                                             "1e300",
                                             "-1e300",
                                             "1.7976931348623157e308",
                                             "nan",
                                             "NaN",
                                             "-nan",
                                             "inf",
                                             "-inf",
                                             "Infinity",
                                             "1e999",
                                             "0x1p-1074",
                                             "1e-12",
                                             "1e12",
                                             "1e19",
                                             "-1e19",
                                             "1e-7",
                                             "1e7",
                                             "0.01",
                                             "179",
                                             "179.5",
                                             "180",
                                             "0.5",
                                             "3",
                                             "-2",
                                             "45",
                                             "6",
                                             ""};

std::string vec3(std::mt19937& rng) {
  std::string text;
  for (int c = 0; c < 3; ++c) text += (c ? "," : "") + kSpellings[rng() % kSpellings.size()];
  return text;
}

TEST(CameraLimits, IssueReproducersAre400NamingTheParameterAndTheServerLives) {
  RunningServer running;
  auto client = running.client();
  const std::string id = addTinyScene(client);
  const std::string image = "/api/scenes/" + id + "/image?width=16&height=12";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"&near=1e-12&far=1e12", "query.near"},
      {"&position=1e19,1,0", "query.position"},
      {"&fov_y_deg=1e-300", "query.fov_y_deg"},
      {"&projection=orthographic&ortho_height=1e300", "query.ortho_height"},
      {"&projection=orthographic&ortho_height=1e-300", "query.ortho_height"},
      {"&far=1e300", "query.far"},
      {"&target=0,-1e300,0", "query.target"},
      {"&up=0,0,0", "query.up"},
      {"&position=0,1,6&target=0,1,6", "query.target"},
      {"&near=4.9e-324", "query.near"},
  };
  for (const auto& [query, path] : cases) {
    const auto res = client.Get((image + query).c_str());
    ASSERT_TRUE(res) << query << ": no answer (the server died?)";
    EXPECT_EQ(res->status, 400) << query << " → " << res->body;
    EXPECT_EQ(bodyJson(res)["error"]["path"], path) << query << " → " << res->body;
  }
  EXPECT_EQ(client.Get(image.c_str())->status, 200);
  EXPECT_EQ(client.Get("/api/health")->status, 200);
}

TEST(CameraLimits, AnUploadedSceneWithAnExtremeCameraIsRefusedAndNotJournaled) {
  TempDataDir data;
  {
    RunningServer running(data.durable());
    auto client = running.client();
    const std::vector<std::pair<json, std::string>> cameras = {
        {{{"position", {0, 1.5, 6}}, {"target", {0, 1, 0}}, {"near", 1e-12}, {"far", 1e12}},
         "camera.near"},
        {{{"position", {1e19, 1, 0}}, {"target", {0, 1, 0}}}, "camera.position"},
        {{{"position", {0, 1.5, 6}}, {"target", {0, 1, 0}}, {"fov_y_deg", 1e-300}},
         "camera.fov_y_deg"},
        {{{"position", {0, 1.5, 6}},
          {"target", {0, 1, 0}},
          {"projection", "orthographic"},
          {"height", 1e300}},
         "camera.height"},
        {{{"position", {0, 1.5, 6}},
          {"target", {0, 1, 0}},
          {"projection", "orthographic"},
          {"height", 1e-300}},
         "camera.height"},
        {{{"position", {0, 1.5, 6}}, {"target", {0, 1, 0}}, {"near", 1e-9}, {"far", 10}},
         "camera.near"},
    };
    for (const auto& [camera, path] : cameras) {
      json scene = tinyScene();
      scene["camera"] = camera;
      const auto res = postJson(client, "/api/scenes?name=bad", scene);
      EXPECT_EQ(res->status, 422) << camera.dump() << " → " << res->body;
      EXPECT_EQ(bodyJson(res)["error"]["path"], path) << res->body;
    }
    EXPECT_EQ(sceneCount(client), 0u);
  }
  RunningServer restarted(data.durable());
  EXPECT_TRUE(restarted.server().restore().empty()) << "a refused scene was journaled";
}

// Seeded: 1,500 /image queries with extreme doubles in every camera parameter, then 300 scene
// uploads with extreme cameras to a journaling server. Every answer is 200 or a 4xx naming a
// query or camera key; a refused upload leaves the scene list as it was, and a restart finds
// only the scenes kept (the accepted ones are deleted as they go).
TEST(CameraLimits, ExtremeDoublesInImageQueriesAndSceneCamerasNeverCrashTheServer) {
  TempDataDir data;
  auto running = std::make_unique<RunningServer>(data.durable());
  auto client = running->client();
  const std::string id = addTinyScene(client);
  std::mt19937 rng(36);
  const char* keys[] = {"position", "target", "up", "fov_y_deg", "ortho_height", "near", "far"};
  size_t ok = 0, refused = 0;
  for (int i = 0; i < 1500; ++i) {
    std::string query = "/api/scenes/" + id + "/image?width=" + std::to_string(1 + rng() % 6) +
                        "&height=" + std::to_string(1 + rng() % 6);
    if (rng() % 2) query += rng() % 2 ? "&projection=orthographic" : "&projection=perspective";
    for (const char* key : keys) {
      if (rng() % 3) continue;
      const bool isVector = std::string(key) == "position" || std::string(key) == "target" ||
                            std::string(key) == "up";
      query += std::string("&") + key + "=" +
               (isVector ? vec3(rng) : kSpellings[rng() % kSpellings.size()]);
    }
    const auto res = client.Get(query.c_str());
    ASSERT_TRUE(res) << query << ": no answer (the server died?)";
    ASSERT_TRUE(res->status == 200 || res->status == 400)
        << query << " → " << res->status << " " << res->body;
    if (res->status == 200) {
      ++ok;
    } else {
      ++refused;
      const std::string path = bodyJson(res)["error"]["path"];
      EXPECT_TRUE(path.rfind("query.", 0) == 0) << query << " → " << res->body;
    }
  }
  EXPECT_GT(ok, 100u) << "the generator should also make valid cameras";
  EXPECT_GT(refused, 500u);

  const double numbers[] = {
      0.0,   -0.0, 4.9e-324, 2.2e-308, 1e-300, 1e300, -1e300, 1.7976931348623157e308,
      1e-12, 1e12, 1e19,     1e-7,     0.01,   179,   180,    0.5,
      3,     -2,   45,       6};
  auto number = [&] { return numbers[rng() % std::size(numbers)]; };
  size_t kept = 0;
  for (int i = 0; i < 300; ++i) {
    json camera = {{"position", {number(), number(), number()}},
                   {"target", {number(), number(), number()}}};
    if (rng() % 2) camera["up"] = {number(), number(), number()};
    if (rng() % 2) camera["projection"] = rng() % 2 ? "orthographic" : "perspective";
    for (const char* key : {"fov_y_deg", "height", "near", "far"})
      if (rng() % 2) camera[key] = number();
    if (i % 4 == 0)
      camera = {
          {"position", {0, 1.5, 6}}, {"target", {0, 1, 0}}, {"near", number()}, {"far", number()}};
    json scene = tinyScene();
    scene["camera"] = camera;
    const auto res = postJson(client, "/api/scenes?name=fuzz", scene);
    ASSERT_TRUE(res) << camera.dump() << ": no answer";
    ASSERT_TRUE(res->status == 201 || res->status == 422) << camera.dump() << " → " << res->body;
    if (res->status == 422) {
      EXPECT_EQ(bodyJson(res)["error"]["path"].get<std::string>().rfind("camera", 0), 0u)
          << res->body;
      EXPECT_EQ(sceneCount(client), 1u) << "a refused upload left a scene";
      continue;
    }
    // Accepted: its own camera renders.
    const std::string created = bodyJson(res)["id"];
    const auto image = client.Get(("/api/scenes/" + created + "/image?width=4&height=3").c_str());
    ASSERT_TRUE(image) << camera.dump() << ": no answer to the image";
    EXPECT_EQ(image->status, 200) << camera.dump() << " → " << image->body;
    EXPECT_EQ(client.Delete(("/api/scenes/" + created).c_str())->status, 204);
    ++kept;
  }
  EXPECT_GT(kept, 10u) << "the generator should also make valid cameras";
  EXPECT_EQ(client.Get("/api/health")->status, 200);
  running.reset();
  const std::vector<RestoredScene> restored = HttpServer(data.durable()).restore();
  ASSERT_EQ(restored.size(), 1u) << "a refused upload was journaled";
  EXPECT_EQ(restored[0].id, id);
}

TEST(NumericLimits, CoordinatesTransformsAndRadianceBeyondTheirBoundsAre422NamingTheKey) {
  RunningServer running;
  auto client = running.client();
  auto refused = [&](const json& scene, const std::string& path) {
    const auto res = postJson(client, "/api/scenes?name=bad", scene);
    EXPECT_EQ(res->status, 422) << res->body;
    EXPECT_EQ(bodyJson(res)["error"]["path"], path) << res->body;
  };
  json scene = tinyScene();
  scene["objects"][1]["vertices"][0] = {-1e300, -0.5, -0.5};
  refused(scene, "objects[1].vertices[0]");
  scene = tinyScene();
  scene["objects"][1]["transform"]["translate"] = {0, 1e300, 0};
  refused(scene, "objects[1].transform.translate");
  scene = tinyScene();
  scene["objects"][1]["transform"]["scale"] = {1e300, 1, 1};
  refused(scene, "objects[1].transform.scale");
  scene = tinyScene();
  scene["objects"][1]["transform"]["scale"] = {1e5, 1e5,
                                               1e5};  // within the scale bound, beyond ±1e9 placed
  scene["objects"][1]["transform"]["translate"] = {0, 9.9999e8, 0};
  refused(scene, "objects[1].faces[0]");
  scene = tinyScene();
  scene["lights"][0]["polygon"][0] = {-0.5, 2.9, -1e12};
  refused(scene, "lights[0].polygon[0]");
  scene = tinyScene();
  scene["lights"][0]["radiance"] = {1e300, 1, 1};
  refused(scene, "lights[0].radiance");
  scene = tinyScene();
  scene["objects"][1]["transform"]["rotate_deg"] = {0, 1e300, 0};
  refused(scene, "objects[1].transform.rotate_deg");
  EXPECT_EQ(sceneCount(client), 0u);

  // The same bounds on edits: nothing applied, version 0.
  const std::string id = addTinyScene(client);
  const std::string edits = "/api/scenes/" + id + "/edits";
  const std::vector<std::pair<json, std::string>> frames = {
      {moveFrame("box", 0, 1e300, 0), "edits[0].transform.translate"},
      {{{"edits", {{{"op", "move"}, {"id", "box"}, {"transform", {{"scale", {1e300, 1, 1}}}}}}}},
       "edits[0].transform.scale"},
      {{{"edits",
         {{{"op", "set_light"},
           {"id", "lamp"},
           {"polygon",
            {{-0.5, 2.9, -0.5}, {0.5, 2.9, -0.5}, {0.5, 2.9, 1e12}, {-0.5, 2.9, 0.5}}}}}}},
       "edits[0].polygon[2]"},
      {{{"edits", {{{"op", "set_light"}, {"id", "lamp"}, {"radiance", {1, 1e300, 1}}}}}},
       "edits[0].radiance"},
  };
  for (const auto& [frame, path] : frames) {
    const auto res = postJson(client, edits, frame);
    EXPECT_EQ(res->status, 422) << res->body;
    EXPECT_EQ(bodyJson(res)["error"]["path"], path) << res->body;
  }
  // A volume upload's `translate` too.
  const auto upload = client.Post(
      ("/api/scenes/" + id + "/volumes?name=smoke.nrrd&translate=0,1e300,0").c_str(),
      protocol::readTextFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/volumes/smoke64.nrrd",
                             size_t(1) << 24),
      "application/octet-stream");
  EXPECT_EQ(upload->status, 400) << upload->body;
  EXPECT_EQ(bodyJson(upload)["error"]["path"], "query.translate") << upload->body;
  EXPECT_EQ(bodyJson(client.Get(("/api/scenes/" + id).c_str()))["version"], 0);

  // Image size, samples and GI keys: 400 naming the parameter.
  const std::string image = "/api/scenes/" + id + "/image?";
  const std::vector<std::pair<std::string, std::string>> queries = {
      {"width=1e300&height=4", "query.width"},
      {"width=4&height=-1", "query.height"},
      {"width=0&height=4", "query.width"},
      {"width=4&height=4&samples=1e300", "query.samples"},
      {"width=4&height=4&samples=0", "query.samples"},
      {"width=4&height=4&gi=sensors&threshold=nan", "query.threshold"},
      {"width=4&height=4&gi=sensors&threshold=1e300", "query.threshold"},
      {"width=4&height=4&gi=sensors&sensor_size=-1", "query.sensor_size"},
      {"width=4&height=4&gi=sensors&bounces=1e9", "query.bounces"},
      {"width=4096&height=4096&gi=sensors&sensor_size=64", "query.sensor_size"},
  };
  for (const auto& [query, path] : queries) {
    const auto res = client.Get((image + query).c_str());
    ASSERT_TRUE(res) << query;
    EXPECT_EQ(res->status, 400) << query << " → " << res->body;
    EXPECT_EQ(bodyJson(res)["error"]["path"], path) << query << " → " << res->body;
  }
}

}  // namespace
}  // namespace penumbra::server::test
