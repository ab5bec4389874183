// The REST API over real HTTP on loopback: create, get, edit, mesh (whole, deltas), stats, rebuild,
// health, static files.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "server_fixture.h"
#include "tests/server/binary_mesh_reader.h"

namespace penumbra::server::test {
namespace {

// Receivers by (object, face), as served (with "scene_version").
std::map<ReceiverKey, json> servedReceiversByKey(const json& mesh) {
  std::map<ReceiverKey, json> out;
  for (const json& r : mesh["receivers"])
    out[{r["object"].get<std::string>(), r["face"].get<uint32_t>()}] = r;
  return out;
}

TEST(ServerApi, HealthAnswersOk) {
  RunningServer running;
  auto client = running.client();
  const auto res = client.Get("/api/health");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  const json body = bodyJson(res);
  EXPECT_EQ(body["status"], "ok");
  EXPECT_EQ(body["limits"]["max_body_bytes"], kMaxBodyBytes);
  EXPECT_EQ(body["limits"]["worker_threads"], kWorkerThreads);
  EXPECT_GE(body["edit_threads"]["count"], 1);
  EXPECT_EQ(body["edit_threads"]["nice"], kEditNiceness);
}

TEST(ServerApi, CreateGetEditAdvancesVersion) {
  RunningServer running;
  auto client = running.client();
  auto created =
      client.Post("/api/scenes?name=cornell.scene.json", sceneText("cornell"), "application/json");
  ASSERT_TRUE(created);
  ASSERT_EQ(created->status, 201) << created->body;
  const json createdBody = bodyJson(created);
  const std::string id = createdBody["id"];
  EXPECT_EQ(createdBody["version"], 0);
  EXPECT_EQ(created->get_header_value("Location"), "/api/scenes/" + id);

  const json got = bodyJson(client.Get(("/api/scenes/" + id).c_str()));
  EXPECT_EQ(got["version"], 0);
  EXPECT_EQ(got["scene"]["format"], "penumbra.scene");
  EXPECT_EQ(got["scene"]["objects"].size(), 7u);

  const auto edited =
      client.Post(("/api/scenes/" + id + "/edits").c_str(),
                  moveFrame("short_block", 1.6, 0, 1.5, -17).dump(), "application/json");
  ASSERT_TRUE(edited);
  ASSERT_EQ(edited->status, 200) << edited->body;
  const json result = bodyJson(edited);
  EXPECT_EQ(result["version"], 1);
  EXPECT_TRUE(result["seconds"].contains("remove"));
  EXPECT_TRUE(result["seconds"].contains("add"));
  EXPECT_TRUE(result["seconds"].contains("relight"));
  EXPECT_GT(result["vertices"]["relit"].get<size_t>(), 0u);
  EXPECT_FALSE(result["mesh_changed"].empty());

  const json after = bodyJson(client.Get(("/api/scenes/" + id).c_str()));
  EXPECT_EQ(after["version"], 1);
  for (const json& object : after["scene"]["objects"]) {
    if (object["id"] == "short_block") {
      EXPECT_EQ(object["transform"]["translate"], json({1.6, 0, 1.5}));
    }
  }

  const json list = bodyJson(client.Get("/api/scenes"));
  ASSERT_EQ(list["scenes"].size(), 1u);
  EXPECT_EQ(list["scenes"][0]["id"], id);
  EXPECT_EQ(list["scenes"][0]["version"], 1);
}

// A `since` delta holds exactly the receivers whose mesh changed, and applying it
// to the old whole mesh gives the new whole mesh.
TEST(ServerApi, MeshSinceCarriesOnlyChangedReceivers) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id;
  const json before = bodyJson(client.Get((base + "/mesh").c_str()));
  EXPECT_EQ(before["format"], "penumbra.mesh");
  EXPECT_EQ(before["version"], 1);  // the mesh format's version
  EXPECT_EQ(before["scene_version"], 0);
  EXPECT_TRUE(before["since"].is_null());

  ASSERT_EQ(client
                .Post((base + "/edits").c_str(), moveFrame("tall_block", 3.9, 0, 3.6, 17).dump(),
                      "application/json")
                ->status,
            200);
  const json whole = bodyJson(client.Get((base + "/mesh").c_str()));
  const json delta = bodyJson(client.Get((base + "/mesh?since=0").c_str()));
  EXPECT_EQ(delta["scene_version"], 1);
  EXPECT_EQ(delta["since"], 0);
  EXPECT_TRUE(delta["removed"].empty());
  const size_t all = whole["receivers"].size();
  const size_t changed = delta["receivers"].size();
  EXPECT_GT(changed, 0u);
  EXPECT_LT(changed, all) << "the moved block's shadow cannot change every receiver of the box";

  auto merged = servedReceiversByKey(before);
  bool movedBlockListed = false;
  for (const json& r : delta["receivers"]) {
    EXPECT_EQ(r["scene_version"], 1);
    merged[{r["object"], r["face"]}] = r;
    movedBlockListed |= r["object"] == "tall_block";
  }
  EXPECT_TRUE(movedBlockListed);
  const auto expected = servedReceiversByKey(whole);
  ASSERT_EQ(merged.size(), expected.size());
  for (const auto& [key, receiver] : expected) {
    json a = merged.at(key), b = receiver;
    a.erase("scene_version");
    b.erase("scene_version");
    EXPECT_EQ(a, b) << key.first << " face " << key.second;
  }
  // Nothing changed after the current version.
  EXPECT_TRUE(bodyJson(client.Get((base + "/mesh?since=1").c_str()))["receivers"].empty());
}

TEST(ServerApi, RemovedObjectsAppearInDeltas) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id;
  const json frame = {{"edits", json::array({{{"op", "remove"}, {"id", "short_block"}}})}};
  const auto res = client.Post((base + "/edits").c_str(), frame.dump(), "application/json");
  ASSERT_EQ(res->status, 200) << res->body;
  EXPECT_FALSE(bodyJson(res)["mesh_removed"].empty());
  const json delta = bodyJson(client.Get((base + "/mesh?since=0").c_str()));
  ASSERT_FALSE(delta["removed"].empty());
  for (const json& key : delta["removed"]) EXPECT_EQ(key["object"], "short_block");
  for (const json& r : delta["receivers"]) EXPECT_NE(r["object"], "short_block");
}

TEST(ServerApi, BinaryMeshMatchesJsonMesh) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id;
  const json mesh = bodyJson(client.Get((base + "/mesh").c_str()));
  const auto res = client.Get((base + "/mesh?format=bin").c_str());
  ASSERT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Type"), "application/octet-stream");
  const BinaryMesh bin = parseBinary(res->body);
  EXPECT_EQ(bin.layout, 4u);
  EXPECT_EQ(bin.version, 0u);
  EXPECT_EQ(bin.flags, 0u);
  // A receiver is its parts one after the other (chunks in order, distinct).
  std::vector<BinaryMesh::Part> whole;
  for (const auto& p : bin.parts) {
    if (!whole.empty() && whole.back().object == p.object && whole.back().face == p.face) {
      auto& r = whole.back();
      EXPECT_LT(std::pair(r.x, r.y), std::pair(p.x, p.y));
      for (uint32_t index : p.indices) r.indices.push_back(index + r.vertices);
      r.positions.insert(r.positions.end(), p.positions.begin(), p.positions.end());
      r.irradiance.insert(r.irradiance.end(), p.irradiance.begin(), p.irradiance.end());
      r.classes.insert(r.classes.end(), p.classes.begin(), p.classes.end());
      r.vertices += p.vertices;
      r.triangles += p.triangles;
      r.x = p.x, r.y = p.y;
    } else {
      whole.push_back(p);
    }
  }
  ASSERT_EQ(whole.size(), mesh["receivers"].size());
  size_t vertices = 0, triangles = 0;
  const std::map<std::string, uint8_t> classCode = {{"lit", 0}, {"penumbra", 1}, {"umbra", 2}};
  for (size_t i = 0; i < whole.size(); ++i) {
    const auto& r = whole[i];
    const json& j = mesh["receivers"][i];
    EXPECT_EQ(bin.objects.at(r.object), j["object"]);
    EXPECT_EQ(r.face, j["face"]);
    ASSERT_EQ(r.vertices, j["positions"].size());
    ASSERT_EQ(r.triangles, j["triangles"].size());
    for (size_t v = 0; v < r.vertices; ++v) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(r.positions[3 * v + c], static_cast<float>(j["positions"][v][c].get<double>()));
        // One-channel parts (the light's colour scaled) within 2 ulps, three-channel ones exact.
        EXPECT_TRUE(withinTwoUlps(r.irradiance[3 * v + c], static_cast<float>(j["irradiance"][v][c].get<double>())));
      }
      EXPECT_EQ(r.classes[v], classCode.at(j["class"][v]));
    }
    for (size_t t = 0; t < r.triangles; ++t)
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(r.indices[3 * t + c], j["triangles"][t][c].get<uint32_t>());
    vertices += r.vertices;
    triangles += r.triangles;
  }
  EXPECT_EQ(bin.totalVertices, vertices);
  EXPECT_EQ(bin.totalTriangles, triangles);

  // A delta in binary: flags and since set, only changed parts, each of a receiver the
  // JSON delta lists.
  ASSERT_EQ(client
                .Post((base + "/edits").c_str(), moveFrame("tall_block", 3.9, 0, 3.6, 17).dump(),
                      "application/json")
                ->status,
            200);
  const json delta = bodyJson(client.Get((base + "/mesh?since=0").c_str()));
  const BinaryMesh binDelta =
      parseBinary(client.Get((base + "/mesh?since=0&format=bin").c_str())->body);
  EXPECT_EQ(binDelta.flags, 1u);
  EXPECT_EQ(binDelta.since, 0u);
  EXPECT_EQ(binDelta.version, 1u);
  ASSERT_FALSE(binDelta.parts.empty());
  std::set<std::pair<std::string, uint32_t>> listed;
  for (const json& r : delta["receivers"]) listed.insert({r["object"].get<std::string>(), r["face"].get<uint32_t>()});
  for (const auto& p : binDelta.parts) {
    EXPECT_TRUE(listed.count({binDelta.objects.at(p.object), p.face})) << binDelta.objects.at(p.object);
    EXPECT_EQ(p.version, 1u);
  }
  EXPECT_LT(binDelta.parts.size(), bin.parts.size());
}

uint32_t bigEndian32(const std::string& bytes, size_t at) {
  return uint32_t(uint8_t(bytes[at])) << 24 | uint32_t(uint8_t(bytes[at + 1])) << 16 |
         uint32_t(uint8_t(bytes[at + 2])) << 8 | uint32_t(uint8_t(bytes[at + 3]));
}

TEST(ServerApi, ImageIsAPngOfTheAskedSize) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const auto res = client.Get(("/api/scenes/" + id + "/image?width=48&height=32").c_str());
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200) << res->body;
  EXPECT_EQ(res->get_header_value("Content-Type"), "image/png");
  const std::string& png = res->body;
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(bigEndian32(png, 16), 48u);  // width
  EXPECT_EQ(bigEndian32(png, 20), 32u);  // height
  // Another camera gives another picture.
  const auto moved = client.Get(
      ("/api/scenes/" + id + "/image?width=48&height=32&position=2.78,4,-6&fov_y_deg=60").c_str());
  ASSERT_EQ(moved->status, 200) << moved->body;
  EXPECT_NE(moved->body, png);
  const auto ortho = client.Get(
      ("/api/scenes/" + id + "/image?width=40&height=30&projection=orthographic&ortho_height=6")
          .c_str());
  ASSERT_EQ(ortho->status, 200) << ortho->body;
  EXPECT_EQ(bigEndian32(ortho->body, 16), 40u);
  EXPECT_EQ(bigEndian32(ortho->body, 20), 30u);
}

TEST(ServerApi, GlbIsABinaryGltf) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const auto res = client.Get(("/api/scenes/" + id + "/mesh?format=glb").c_str());
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200) << res->body;
  EXPECT_EQ(res->get_header_value("Content-Type"), "model/gltf-binary");
  ASSERT_GT(res->body.size(), 12u);
  EXPECT_EQ(res->body.substr(0, 4), "glTF");
  uint32_t length = 0;
  std::memcpy(&length, res->body.data() + 8, 4);
  EXPECT_EQ(length, res->body.size());
}

TEST(ServerApi, StatsRebuildAndDelete) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id;
  const json stats = bodyJson(client.Get((base + "/stats").c_str()));
  EXPECT_EQ(stats["version"], 0);
  EXPECT_GT(stats["mesh"]["vertices"].get<size_t>(), 0u);
  EXPECT_TRUE(stats["last_frame"].is_null());
  const auto rebuilt = client.Post((base + "/rebuild").c_str(), "", "application/json");
  ASSERT_EQ(rebuilt->status, 200) << rebuilt->body;
  const json report = bodyJson(rebuilt);
  EXPECT_GT(report["seconds"]["total"].get<double>(), 0.0);
  EXPECT_EQ(report["mesh"]["vertices"], stats["mesh"]["vertices"]);
  EXPECT_FALSE(bodyJson(client.Get((base + "/stats").c_str()))["last_rebuild"].is_null());

  EXPECT_EQ(client.Delete(base.c_str())->status, 204);
  EXPECT_EQ(client.Get(base.c_str())->status, 404);
}

TEST(ServerApi, ServesThePageAndNodeModules) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(PENUMBRA_BINARY_DIR) / "test_server_static";
  fs::remove_all(root);
  fs::create_directories(root / "page");
  fs::create_directories(root / "node_modules/three/build");
  std::ofstream(root / "page/index.html") << "<!doctype html><title>penumbra</title>";
  std::ofstream(root / "page/main.js") << "export const x = 1;";
  std::ofstream(root / "node_modules/three/build/three.module.js")
      << "export const REVISION = '187';";
  ServerOptions options = RunningServer::loopback();
  options.staticDir = (root / "page").string();
  RunningServer running(options);
  auto client = running.client();
  const auto index = client.Get("/");
  ASSERT_EQ(index->status, 200);
  EXPECT_NE(index->body.find("penumbra"), std::string::npos);
  EXPECT_EQ(client.Get("/main.js")->get_header_value("Content-Type"), "text/javascript");
  const auto three = client.Get("/node_modules/three/build/three.module.js");
  ASSERT_EQ(three->status, 200);
  EXPECT_NE(three->body.find("REVISION"), std::string::npos);
  EXPECT_EQ(client.Get("/api/health")->status, 200);
}

}  // namespace
}  // namespace penumbra::server::test
