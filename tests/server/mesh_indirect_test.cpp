// GET /mesh?indirect=1: each vertex's indirect irradiance equals core's gi::vertexIndirect on the
// same mesh (JSON, binary), bytes are stable and unchanged without it, the GLB's COLOR_0 includes
// it (brighter in the shadows), and hostile values are 400 naming their key.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <chrono>
#include <cstring>
#include <optional>
#include <thread>

#include "core/engine/engine.h"
#include "core/gi/sensor_gi.h"
#include "core/raycast/ray_scene.h"
#include "core/util/parallel.h"
#include "server/mesh_binary.h"
#include "server_fixture.h"
#include "tests/server/binary_mesh_reader.h"

namespace penumbra::server::test {
namespace {

// Every vertex's indirect irradiance of a binary mesh with kFlagIndirect, in part order.
std::vector<float> binaryIndirect(const std::string& bytes) {
  const BinaryMesh mesh = parseBinary(bytes);
  EXPECT_EQ(mesh.flags & mesh_binary::kFlagIndirect, mesh_binary::kFlagIndirect);
  std::vector<float> out;
  for (const BinaryMesh::Part& part : mesh.parts) {
    EXPECT_EQ(part.indirect.size(), 3 * size_t(part.vertices));
    out.insert(out.end(), part.indirect.begin(), part.indirect.end());
  }
  return out;
}

TEST(MeshIndirect, ValuesEqualCoreVertexIndirectInJsonAndBinary) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id + "/mesh?";
  const json plain = bodyJson(client.Get((base + "format=json").c_str()));
  const json withIndirect =
      bodyJson(client.Get((base + "format=json&indirect=1&sensor_size=6").c_str()));
  EXPECT_FALSE(plain["receivers"][0].contains("indirect"));  // old clients see what they saw
  EXPECT_EQ(withIndirect["indirect"]["sensor_size"], 6);

  Engine engine(protocol::loadSceneFile(scenePath("cornell")));
  const RayScene rays(engine.scene());
  const Mesh expected = gi::vertexIndirect(engine.scene(), rays, engine.mesh(), 6, 1, Parallel(0));
  ASSERT_EQ(withIndirect["receivers"].size(), expected.receivers.size());
  std::vector<float> flat;
  double largest = 0;
  for (size_t r = 0; r < expected.receivers.size(); ++r) {
    const json& values = withIndirect["receivers"][r]["indirect"];
    EXPECT_EQ(withIndirect["receivers"][r]["irradiance"], plain["receivers"][r]["irradiance"]);
    ASSERT_EQ(values.size(), expected.receivers[r].irradiance.size());
    for (size_t v = 0; v < values.size(); ++v)
      for (int c = 0; c < 3; ++c) {
        const double e = expected.receivers[r].irradiance[v][c];
        EXPECT_DOUBLE_EQ(values[v][size_t(c)].get<double>(), e);
        flat.push_back(float(e));
        largest = std::max(largest, e);
      }
  }
  EXPECT_GT(largest, 0);

  const auto first = client.Get((base + "format=bin&indirect=1&sensor_size=6").c_str());
  const auto again = client.Get((base + "format=bin&indirect=1&sensor_size=6").c_str());
  ASSERT_EQ(first->status, 200);
  EXPECT_EQ(first->body, again->body);  // stable bytes
  EXPECT_EQ(again->get_header_value("X-Penumbra-Indirect-Cached"), "1");
  EXPECT_EQ(binaryIndirect(first->body), flat);
  // Without indirect=1: the same layout without the indirect arrays, no flag.
  const std::string bytes = client.Get((base + "format=bin").c_str())->body;
  EXPECT_EQ(bytes, client.Get((base + "format=bin&indirect=0").c_str())->body);
  uint32_t flags;
  std::memcpy(&flags, bytes.data() + 12, 4);
  EXPECT_EQ(flags, 0u);
  EXPECT_EQ(bytes.size() + 12 * (flat.size() / 3), first->body.size());
}

TEST(MeshIndirect, AnEditBakesTheNewVersion) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const std::string url = "/api/scenes/" + id + "/mesh?format=bin&indirect=1&sensor_size=4";
  const auto before = client.Get(url.c_str());
  EXPECT_EQ(before->get_header_value("X-Penumbra-Indirect-Cached"), "0");
  json translate;
  const json served = bodyJson(client.Get(("/api/scenes/" + id).c_str()));
  for (const json& object : served["scene"]["objects"])
    if (object["id"] == "short_block") translate = object["transform"]["translate"];
  ASSERT_TRUE(translate.is_array());
  const json frame = moveFrame("short_block", translate[0].get<double>() + 0.05,
                               translate[1].get<double>(), translate[2].get<double>(), -17);
  ASSERT_EQ(postJson(client, "/api/scenes/" + id + "/edits", frame)->status, 200);
  const auto after = client.Get(url.c_str());
  EXPECT_EQ(after->get_header_value("X-Penumbra-Version"), "1");
  EXPECT_EQ(after->get_header_value("X-Penumbra-Indirect-Cached"), "0");
  EXPECT_NE(binaryIndirect(before->body), binaryIndirect(after->body));
}

// A bake runs outside the engine: an edit and a plain mesh read sent while it runs answer long
// before it ends; the bake is of the version it started from, and a second request shares it.
TEST(MeshIndirect, EditsAndReadsDoNotWaitForABake) {
  RunningServer running;
  const std::string id = running.addBundled("cubes15");
  const std::string url = "/api/scenes/" + id + "/mesh?format=bin&indirect=1&sensor_size=16";
  std::optional<Reply> baking, sharing;
  std::thread first([&] { baking.emplace(running.client().Get(url.c_str())); });
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  std::thread second([&] { sharing.emplace(running.client().Get(url.c_str())); });
  auto client = running.client();
  const auto start = std::chrono::steady_clock::now();
  const json served = bodyJson(client.Get(("/api/scenes/" + id).c_str()));
  const json& cube = served["scene"]["objects"].back();
  json frame = moveFrame(cube["id"], 0, 0, 0);
  frame["edits"][0]["transform"] = cube["transform"];
  frame["edits"][0]["transform"]["translate"][0] = cube["transform"]["translate"][0].get<double>() + 0.01;
  const auto edit = postJson(client, "/api/scenes/" + id + "/edits", frame);
  const auto plain = client.Get(("/api/scenes/" + id + "/mesh?format=bin").c_str());
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  first.join();
  second.join();
  ASSERT_EQ(edit->status, 200) << edit->body;
  ASSERT_EQ(plain->status, 200);
  ASSERT_TRUE(*baking && *sharing);
  ASSERT_EQ((*baking)->status, 200);
  const double bakeSeconds = std::stod((*baking)->get_header_value("X-Penumbra-Indirect-Seconds"));
  EXPECT_LT(waited, bakeSeconds / 2) << "edit + read " << waited << " s, bake " << bakeSeconds << " s";
  EXPECT_EQ((*baking)->get_header_value("X-Penumbra-Version"), "0");
  EXPECT_EQ(plain->get_header_value("X-Penumbra-Version"), "1");
  EXPECT_EQ((*baking)->get_header_value("X-Penumbra-Indirect-Cached"), "0");
  EXPECT_EQ((*sharing)->get_header_value("X-Penumbra-Indirect-Cached"), "1");
  EXPECT_EQ((*baking)->body, (*sharing)->body);
}

std::vector<float> colorsOf(const std::string& glb) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  EXPECT_TRUE(loader.LoadBinaryFromMemory(&model, &err, &warn,
                                          reinterpret_cast<const unsigned char*>(glb.data()),
                                          unsigned(glb.size())))
      << err;
  std::vector<float> out;  // every object mesh's exact _RADIANCE, in mesh order (lights have none)
  for (const tinygltf::Mesh& mesh : model.meshes) {
    if (!mesh.primitives[0].attributes.count("_RADIANCE")) continue;
    const tinygltf::Accessor& a =
        model.accessors[size_t(mesh.primitives[0].attributes.at("_RADIANCE"))];
    const tinygltf::BufferView& view = model.bufferViews[size_t(a.bufferView)];
    const size_t begin = out.size();
    out.resize(begin + 3 * a.count);
    std::memcpy(out.data() + begin, model.buffers[0].data.data() + view.byteOffset + a.byteOffset,
                12 * a.count);
  }
  return out;
}

TEST(MeshIndirect, GlbRadianceIncludesIndirectLightAndIsBrighterInShadow) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id + "/mesh?format=glb&color_scale=1";
  const std::vector<float> direct = colorsOf(client.Get(base.c_str())->body);
  const std::vector<float> bounced = colorsOf(client.Get((base + "&indirect=1").c_str())->body);
  ASSERT_EQ(direct.size(), bounced.size());
  EXPECT_NE(direct, bounced);
  // Vertices in umbra (direct radiance 0): indirect light only, so brighter; nothing gets darker.
  size_t shadowed = 0, brighter = 0;
  for (size_t i = 0; i < direct.size(); ++i) {
    EXPECT_GE(bounced[i], direct[i] - 1e-6f);
    if (direct[i] == 0) {
      ++shadowed;
      if (bounced[i] > 0) ++brighter;
    }
  }
  EXPECT_GT(shadowed, 0u);
  EXPECT_GT(double(brighter), 0.9 * double(shadowed));
}

TEST(MeshIndirect, HostileValuesAre400WithTheirPath) {
  RunningServer running;
  const std::string id = running.addBundled("cubes15");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id + "/mesh?format=bin";
  const std::pair<std::string, std::string> cases[] = {
      {"&indirect=2", "query.indirect"},
      {"&indirect=yes", "query.indirect"},
      {"&indirect=-1", "query.indirect"},
      {"&indirect=", "query.indirect"},
      {"&indirect=1&sensor_size=0", "query.sensor_size"},
      {"&indirect=1&sensor_size=65", "query.sensor_size"},
      {"&indirect=1&sensor_size=1e9", "query.sensor_size"},
      {"&indirect=1&bounces=0", "query.bounces"},
      {"&indirect=1&bounces=5", "query.bounces"},
      {"&sensor_size=8", "query.sensor_size"},  // a bake setting without indirect=1
      {"&indirect=0&bounces=2", "query.bounces"},
      {"&indirect=1&since=0", "query.since"},
      {"&indirect=1&sensor_size=64&bounces=4", "query.sensor_size"},  // past the ray budget
  };
  for (const auto& [query, path] : cases) {
    const auto res = client.Get((base + query).c_str());
    ASSERT_TRUE(res) << query;
    EXPECT_EQ(res->status, 400) << query << " → " << res->body;
    EXPECT_EQ(bodyJson(res)["error"]["path"], path) << query;
  }
}

}  // namespace
}  // namespace penumbra::server::test
