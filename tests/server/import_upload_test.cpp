// Creating scenes from files made elsewhere over real HTTP (POST /api/scenes?format=obj|gltf|glb):
// OBJ + MTL as a form, raw bodies, options, refusals that create nothing, and the lit mesh as GLB
// read back with tinygltf (counts per object, colours = albedo/π × irradiance × the scale).
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <sstream>

#include "server_fixture.h"

namespace penumbra::server::test {
namespace {

const std::string kData = std::string(PENUMBRA_SOURCE_DIR) + "/tests/interchange/data/";

std::string dataText(const std::string& name) {
  return protocol::readTextFile(kData + name, protocol::kMaxJsonFileBytes);
}

httplib::MultipartFormDataItems cornellForm() {
  return {{"file", dataText("cornell_mm.obj"), "cornell_mm.obj", "model/obj"},
          {"mtl", dataText("cornell_mm.mtl"), "cornell_mm.mtl", "text/plain"}};
}

size_t sceneCount(TestClient& client) {
  return bodyJson(client.Get("/api/scenes"))["scenes"].size();
}

// A floor, a card above it and an emissive lamp (facing up: the importer turns it), as GLB or
// glTF with its buffer embedded as a data: URI.
std::vector<uint8_t> smallGltf(bool binary, const std::string& bufferUri = "") {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.buffers.emplace_back();
  model.scenes.emplace_back();
  model.defaultScene = 0;
  auto material = [&](const Vec3& base, const Vec3& emissive) {
    tinygltf::Material m;
    m.pbrMetallicRoughness.baseColorFactor = {base.x, base.y, base.z, 1};
    m.emissiveFactor = {emissive.x, emissive.y, emissive.z};
    model.materials.push_back(m);
    return int(model.materials.size() - 1);
  };
  auto append = [&](const void* data, size_t bytes, size_t count, int componentType, int type) {
    std::vector<unsigned char>& buffer = model.buffers[0].data;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buffer.size();
    view.byteLength = bytes;
    buffer.resize(buffer.size() + bytes);
    std::memcpy(buffer.data() + view.byteOffset, data, bytes);
    model.bufferViews.push_back(view);
    tinygltf::Accessor a;
    a.bufferView = int(model.bufferViews.size() - 1);
    a.componentType = componentType;
    a.type = type;
    a.count = count;
    if (type == TINYGLTF_TYPE_VEC3) a.minValues = {-10, -10, -10}, a.maxValues = {10, 10, 10};
    model.accessors.push_back(a);
    return int(model.accessors.size() - 1);
  };
  auto quad = [&](const std::string& name, float half, float y, int mat) {
    const std::vector<float> p = {-half, y, -half, -half, y, half, half, y, half, half, y, -half};
    const std::vector<uint32_t> i = {0, 1, 2, 0, 2, 3};
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    primitive.material = mat;
    primitive.attributes["POSITION"] =
        append(p.data(), p.size() * 4, 4, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
    primitive.indices = append(i.data(), i.size() * 4, 6, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                               TINYGLTF_TYPE_SCALAR);
    tinygltf::Mesh mesh;
    mesh.primitives.push_back(primitive);
    model.meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = name;
    node.mesh = int(model.meshes.size() - 1);
    model.nodes.push_back(node);
    model.scenes[0].nodes.push_back(int(model.nodes.size() - 1));
  };
  const int grey = material({0.5, 0.6, 0.7}, {0, 0, 0});
  quad("floor", 2, 0, grey);
  quad("card", 0.5, 1, grey);
  quad("lamp", 0.5, 3, material({1, 1, 1}, {1, 0.5, 0.25}));
  if (!bufferUri.empty()) model.buffers[0].uri = bufferUri;
  tinygltf::TinyGLTF writer;
  std::ostringstream out;
  EXPECT_TRUE(writer.WriteGltfSceneToStream(&model, out, false, binary));
  std::string text = out.str();
  if (!bufferUri.empty()) {  // tinygltf embeds buffers: point the buffer at a file instead
    const size_t at = text.find("data:application/octet-stream;base64,");
    const size_t end = text.find('"', at);
    if (at != std::string::npos) text.replace(at, end - at, bufferUri);
  }
  return std::vector<uint8_t>(text.begin(), text.end());
}

std::string asString(const std::vector<uint8_t>& bytes) {
  return std::string(bytes.begin(), bytes.end());
}

std::vector<float> floatsOf(const tinygltf::Model& model, int index) {
  const tinygltf::Accessor& a = model.accessors[size_t(index)];
  EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  const tinygltf::BufferView& view = model.bufferViews[size_t(a.bufferView)];
  const size_t n = a.count * size_t(tinygltf::GetNumComponentsInType(uint32_t(a.type)));
  std::vector<float> out(n);
  std::memcpy(out.data(),
              model.buffers[size_t(view.buffer)].data.data() + view.byteOffset + a.byteOffset,
              n * 4);
  return out;
}

TEST(ServerImport, CornellObjWithMtlAsAFormBecomesAServedSceneWithItsLight) {
  RunningServer running;
  auto client = running.client();
  const auto created = client.Post("/api/scenes?scale=0.001", cornellForm());
  ASSERT_TRUE(created);
  ASSERT_EQ(created->status, 201) << created->body;
  const json body = bodyJson(created);
  EXPECT_EQ(body["id"], "cornell_mm");
  EXPECT_EQ(body["name"], "cornell_mm.obj");
  EXPECT_EQ(body["version"], 0);
  EXPECT_GT(body["receivers"].get<int>(), 0);
  const json& report = body["import"];
  EXPECT_EQ(report["source"], "cornell_mm.obj");
  EXPECT_EQ(report["format"], "obj");
  EXPECT_EQ(report["lights"], 1);
  EXPECT_EQ(report["objects"], body["objects"]);
  EXPECT_EQ(report["faces"], body["faces"]);
  EXPECT_GE(report["seconds"].get<double>(), 0.0);
  EXPECT_FALSE(report["repairs"].contains("missing_material_files")) << report.dump();
  // The left wall is not planar in the file: split, and said so.
  EXPECT_GE(report["repairs"].value("non_planar_polygons_split", 0), 1) << report.dump();

  const json scene = bodyJson(client.Get("/api/scenes/cornell_mm"))["scene"];
  ASSERT_EQ(scene["lights"].size(), 1u);
  EXPECT_EQ(scene["lights"][0]["radiance"], json({17.0, 12.0, 4.0}));
  for (const json& corner : scene["lights"][0]["polygon"]) {  // the ceiling's plane, in metres
    EXPECT_NEAR(corner[1].get<double>(), 0.5488, 1e-12);
    EXPECT_GE(corner[0].get<double>(), 0.213 - 1e-12);
    EXPECT_LE(corner[0].get<double>(), 0.343 + 1e-12);
  }
}

TEST(ServerImport, RawObjBodyWithoutMtlCountsItAsMissingAndTakesTheRadianceOption) {
  RunningServer running;
  auto client = running.client();
  const auto created = client.Post("/api/scenes?format=obj&name=box&scale=0.001&light_radiance=5",
                                   dataText("cornell_mm.obj"), "model/obj");
  ASSERT_TRUE(created);
  ASSERT_EQ(created->status, 201) << created->body;
  const json body = bodyJson(created);
  EXPECT_EQ(body["id"], "box");
  EXPECT_EQ(body["import"]["source"], "box.obj");
  EXPECT_EQ(body["import"]["repairs"]["missing_material_files"], 1);
  const json scene = bodyJson(client.Get("/api/scenes/box"))["scene"];
  ASSERT_EQ(scene["lights"].size(), 1u);
  EXPECT_EQ(scene["lights"][0]["radiance"], json({5.0, 5.0, 5.0}));
}

// A model without lights (what a user drops in first) is served in the default studio; the
// report says where it went and what its surface is (interchange/default_studio.h).
TEST(ServerImport, BareModelGoesIntoTheDefaultStudio) {
  RunningServer running;
  auto client = running.client();
  const std::string tetra = "o tetra\nv 0 0 0\nv 100 0 0\nv 0 100 0\nv 0 0 100\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 4 3\n";
  const auto created = client.Post("/api/scenes?format=obj&name=tetra.obj", tetra, "model/obj");
  ASSERT_TRUE(created);
  ASSERT_EQ(created->status, 201) << created->body;
  const json report = bodyJson(created)["import"];
  EXPECT_EQ(report["studio"]["scale"], 0.01) << report.dump();
  EXPECT_NE(report["studio"]["sentence"].get<std::string>().find("no lights in tetra.obj: placed it in the default studio"),
            std::string::npos);
  EXPECT_EQ(report["meshes"][0]["object"], "tetra");
  EXPECT_EQ(report["meshes"][0]["closed_components"], 1);
  EXPECT_EQ(report["meshes"][0]["faces_flipped"], 1);  // its last face was wound inward
  const json scene = bodyJson(client.Get("/api/scenes/tetra"))["scene"];
  ASSERT_EQ(scene["lights"].size(), 1u);
  EXPECT_EQ(scene["objects"].size(), 7u);  // the model and the room's six quads
}

TEST(ServerImport, MtllibPathsMatchUploadedBaseNames) {
  RunningServer running;
  auto client = running.client();
  std::string obj = dataText("cornell_mm.obj");
  const size_t at = obj.find("mtllib cornell_mm.mtl");
  ASSERT_NE(at, std::string::npos);
  obj.replace(at, 21, "mtllib materials/cornell_mm.mtl");
  const auto created = client.Post(
      "/api/scenes?scale=0.001",
      httplib::MultipartFormDataItems{{"file", obj, "box.obj", ""},
                                      {"mtl", dataText("cornell_mm.mtl"), "cornell_mm.mtl", ""}});
  ASSERT_TRUE(created);
  ASSERT_EQ(created->status, 201) << created->body;
  EXPECT_FALSE(bodyJson(created)["import"]["repairs"].contains("missing_material_files"));
}

TEST(ServerImport, BadFilesAre422WithTheImportersPathAndCreateNothing) {
  RunningServer running;
  auto client = running.client();
  running.addBundled("cornell");
  struct Case {
    std::string format, body, path;
  };
  const std::vector<Case> cases = {
      {"obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n", "(obj)"},              // index past the vertices
      {"obj&studio=0", "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n", "(import)"},  // no light, no studio
      {"obj", "# only a comment\n", "(import)"},                    // no faces
      {"glb", "glTF\x02\0\0\0garbage", "(gltf)"},                   // truncated GLB
      {"gltf", "{\"asset\": {\"version\": \"2.0\"}, \"scenes\": [", "(gltf)"},  // broken JSON
      // An upload may not read the server's files.
      {"gltf", asString(smallGltf(false, "/etc/hostname")), "(gltf)"},
  };
  for (const Case& c : cases) {
    const auto res =
        client.Post(("/api/scenes?format=" + c.format).c_str(), c.body, "application/octet-stream");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 422) << c.format << ": " << res->body;
    const json error = bodyJson(res)["error"];
    EXPECT_EQ(error["code"], "invalid_scene") << res->body;
    EXPECT_EQ(error["path"], c.path) << res->body;
    EXPECT_FALSE(error["message"].get<std::string>().empty());
    EXPECT_EQ(sceneCount(client), 1u) << "a refused upload creates no scene";
  }
  // A file requiring an extension the importer does not read: refused naming it.
  const auto instanced = client.Post(
      "/api/scenes?format=gltf",
      R"({"asset": {"version": "2.0"}, "extensionsUsed": ["EXT_mesh_gpu_instancing"],
          "extensionsRequired": ["EXT_mesh_gpu_instancing"]})",
      "application/octet-stream");
  ASSERT_TRUE(instanced);
  EXPECT_EQ(instanced->status, 422) << instanced->body;
  EXPECT_EQ(bodyJson(instanced)["error"]["path"], "extensionsRequired[0]") << instanced->body;
  EXPECT_NE(instanced->body.find("EXT_mesh_gpu_instancing"), std::string::npos) << instanced->body;
  EXPECT_EQ(sceneCount(client), 1u);
  // An MTL that breaks nothing but the OBJ's faces: still refused whole.
  const auto res = client.Post(
      "/api/scenes",
      httplib::MultipartFormDataItems{{"file", "f 1 2 3\n", "bad.obj", ""},
                                      {"mtl", dataText("cornell_mm.mtl"), "cornell_mm.mtl", ""}});
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 422) << res->body;
  EXPECT_EQ(sceneCount(client), 1u);
}

TEST(ServerImport, MalformedRequestsAre400NamingTheParameterOrPart) {
  RunningServer running;
  auto client = running.client();
  struct Case {
    std::string query;
    httplib::MultipartFormDataItems form;  // empty: the body is the Cornell OBJ
    std::string path;
  };
  const std::vector<Case> cases = {
      {"format=fbx", {}, "query.format"},
      {"format=obj&scale=-1", {}, "query.scale"},
      {"format=obj&scale=abc", {}, "query.scale"},
      {"format=obj&light_radiance=1,2", {}, "query.light_radiance"},
      {"format=obj&light_radiance=1,-2,3", {}, "query.light_radiance"},
      {"scale=0.001", {}, "query.scale"},  // options without an import
      {"format=obj&studio=yes", {}, "query.studio"},
      {"studio=0", {}, "query.studio"},
      {"", {{"mtl", "newmtl a\n", "a.mtl", ""}}, "(form).file"},
      {"", {{"file", "v 0 0 0\n", "box.txt", ""}}, "(form).file"},  // format unknown
      {"", {{"file", "v 0 0 0\n", "box.obj", ""}, {"extra", "x", "x.txt", ""}}, "(form).extra"},
      {"format=glb",
       {{"file", "glTF", "a.glb", ""}, {"mtl", "newmtl a\n", "a.mtl", ""}},
       "(form).mtl"},
      {"", {{"file", "", "empty.obj", ""}}, "(form).file"},
  };
  for (const Case& c : cases) {
    const std::string path = "/api/scenes?" + c.query;
    const auto res = c.form.empty()
                         ? client.Post(path.c_str(), dataText("cornell_mm.obj"), "model/obj")
                         : client.Post(path.c_str(), c.form);
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 400) << c.query << ": " << res->body;
    EXPECT_EQ(bodyJson(res)["error"]["path"], c.path) << c.query << ": " << res->body;
  }
  EXPECT_EQ(sceneCount(client), 0u);
}

TEST(ServerImport, SceneJsonStillWorksWithFormatScene) {
  RunningServer running;
  auto client = running.client();
  const auto created =
      client.Post("/api/scenes?format=scene&name=c", sceneText("cornell"), "application/json");
  ASSERT_TRUE(created);
  ASSERT_EQ(created->status, 201) << created->body;
  EXPECT_FALSE(bodyJson(created).contains("import"));
}

// GLB in (a file made here with tinygltf), lit mesh out as GLB, read back with tinygltf and
// compared with the mesh JSON of the same version: per object the receivers' vertices in mesh
// order then each dark face's corners; COLOR_0 = albedo/π × E × the served scale.
TEST(ServerImport, GlbUploadRoundTripsToAGlbOfTheLitMesh) {
  RunningServer running;
  auto client = running.client();
  const auto created = client.Post("/api/scenes?format=glb&name=small", asString(smallGltf(true)),
                                   "model/gltf-binary");
  ASSERT_TRUE(created);
  ASSERT_EQ(created->status, 201) << created->body;
  const json body = bodyJson(created);
  EXPECT_EQ(body["import"]["format"], "glb");
  EXPECT_EQ(body["import"]["lights"], 1);
  EXPECT_EQ(body["import"]["repairs"]["lights_turned_to_face_the_scene"], 1);
  EXPECT_EQ(body["objects"], 2);
  const std::string id = body["id"];

  // The same content as .gltf with an embedded buffer (raw body) imports the same.
  const auto gltf = client.Post("/api/scenes?format=gltf&name=small_gltf",
                                asString(smallGltf(false)), "model/gltf+json");
  ASSERT_TRUE(gltf);
  ASSERT_EQ(gltf->status, 201) << gltf->body;
  EXPECT_EQ(bodyJson(gltf)["faces"], body["faces"]);

  const Scene scene =
      protocol::sceneFromJson(bodyJson(client.Get(("/api/scenes/" + id).c_str()))["scene"]);
  const json meshJson = bodyJson(client.Get(("/api/scenes/" + id + "/mesh").c_str()));
  const auto glbRes = client.Get(("/api/scenes/" + id + "/mesh?format=glb").c_str());
  ASSERT_TRUE(glbRes);
  ASSERT_EQ(glbRes->status, 200) << glbRes->body;
  EXPECT_EQ(glbRes->get_header_value("Content-Type"), "model/gltf-binary");
  const double headerScale = std::stod(glbRes->get_header_value("X-Penumbra-Color-Scale"));

  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromMemory(
      &model, &err, &warn, reinterpret_cast<const unsigned char*>(glbRes->body.data()),
      unsigned(glbRes->body.size())))
      << err;
  const double scale = model.asset.extras.Get("penumbra").Get("color_scale").GetNumberAsDouble();
  EXPECT_DOUBLE_EQ(scale, headerScale);
  ASSERT_EQ(model.meshes.size(), scene.objects().size() + scene.lights().size());  // + a mesh per light
  Vec3 ambient(0.0);
  for (int c = 0; c < 3; ++c) ambient[c] = model.asset.extras.Get("penumbra").Get("ambient").Get(c).GetNumberAsDouble();
  EXPECT_GT(ambient.x + ambient.y + ambient.z, 0);

  double brightest = 0;
  for (size_t i = 0; i < scene.objects().size(); ++i) {
    const std::string& objectId = scene.objects()[i].id;
    const tinygltf::Mesh& mesh = model.meshes[i];
    EXPECT_EQ(mesh.name, objectId);
    const std::vector<float> positions =
        floatsOf(model, mesh.primitives[0].attributes.at("POSITION"));
    const std::vector<float> colors = floatsOf(model, mesh.primitives[0].attributes.at("COLOR_0"));
    const std::vector<float> exact = floatsOf(model, mesh.primitives[0].attributes.at("_RADIANCE"));
    size_t v = 0, darkCorners = 0;
    std::vector<bool> received(scene.objects()[i].faces.size(), false);
    for (const json& r : meshJson["receivers"]) {
      if (r["object"] != objectId) continue;
      const uint32_t face = r["face"];
      received[face] = true;
      const Vec3 albedo = scene.albedo(FaceId{scene.handleOf(i), face});
      for (size_t k = 0; k < r["positions"].size(); ++k, ++v) {
        ASSERT_LT(3 * v + 2, positions.size());
        for (int c = 0; c < 3; ++c) {
          EXPECT_FLOAT_EQ(positions[3 * v + size_t(c)], float(r["positions"][k][c].get<double>()));
          const double radiance = albedo[c] / M_PI * r["irradiance"][k][c].get<double>();
          EXPECT_FLOAT_EQ(exact[3 * v + size_t(c)], float(radiance));
          // The display colour: the page's exposure with the ambient fill, clamped.
          EXPECT_FLOAT_EQ(colors[3 * v + size_t(c)], float(std::min(1.0, (radiance + albedo[c] / M_PI * ambient[c]) * scale)));
          brightest = std::max(brightest, double(colors[3 * v + size_t(c)]));
        }
      }
    }
    for (const Face& face : scene.faces())
      if (face.id.object == scene.handleOf(i) && !received[face.id.face])
        darkCorners += face.polygon.size();
    EXPECT_EQ(positions.size() / 3, v + darkCorners) << objectId;
  }
  EXPECT_FLOAT_EQ(float(brightest), 1.0f) << "the default scale shows the 99th percentile at 1";

  // A fixed scale is honoured; a bad one is refused.
  const auto fixed = client.Get(("/api/scenes/" + id + "/mesh?format=glb&color_scale=0.5").c_str());
  ASSERT_TRUE(fixed);
  EXPECT_EQ(fixed->get_header_value("X-Penumbra-Color-Scale"), "0.5");
  const auto bad = client.Get(("/api/scenes/" + id + "/mesh?format=glb&color_scale=0").c_str());
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  EXPECT_EQ(bodyJson(bad)["error"]["path"], "query.color_scale");
}

}  // namespace
}  // namespace penumbra::server::test
