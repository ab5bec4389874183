// Mesh JSON v1: the writer's layout, exact write/read round trips, and the
// reader's refusals with key paths.
#include <filesystem>
#include <random>
#include <sstream>

#include <unistd.h>

#include <gtest/gtest.h>

#include "protocol/json_text.h"
#include "protocol/mesh_json.h"
#include "protocol/scene_json.h"
#include "scene_fixtures.h"

namespace penumbra::protocol {
namespace {

using nlohmann::json;

// A fan mesh per receiving face (corners + centroid) with random full-precision
// values: shaped like an exported mesh, independent of any engine.
Mesh fanMesh(const Scene& scene, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> value(0.0, 20.0);
  Mesh mesh;
  for (const Face& face : scene.faces()) {
    if (!scene.receivesLight(face)) continue;
    ReceiverMesh r;
    r.face = face.id;
    r.normal = face.plane.normal;
    r.positions = face.polygon;
    r.positions.push_back(centroid(face.polygon));
    const uint32_t center = uint32_t(r.positions.size() - 1);
    for (uint32_t i = 0; i < center; ++i) r.triangles.push_back({i, (i + 1) % center, center});
    for (size_t i = 0; i < r.positions.size(); ++i) {
      r.irradiance.push_back(Vec3(value(rng), value(rng), value(rng)));
      r.classes.push_back(LightClass(rng() % 3));
    }
    mesh.receivers.push_back(std::move(r));
  }
  return mesh;
}

void expectSameMesh(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.receivers.size(), b.receivers.size());
  for (size_t i = 0; i < a.receivers.size(); ++i) {
    const ReceiverMesh &x = a.receivers[i], &y = b.receivers[i];
    EXPECT_EQ(x.face, y.face);
    EXPECT_EQ(x.normal, y.normal);
    EXPECT_EQ(x.positions, y.positions);
    EXPECT_EQ(x.irradiance, y.irradiance);
    EXPECT_EQ(x.classes, y.classes);
    EXPECT_EQ(x.triangles, y.triangles);
  }
}

class MeshJson : public ::testing::Test {
 protected:
  Scene scene = sceneFromJson(testing::baseSceneJson());
  Mesh mesh = fanMesh(scene, 7);
};

TEST_F(MeshJson, WriterFollowsTheFormat) {
  ASSERT_FALSE(mesh.receivers.empty());
  const json out = meshToJson(scene, mesh, "office.scene.json");
  EXPECT_EQ(out["format"], "penumbra.mesh");
  EXPECT_EQ(out["version"], 1);
  EXPECT_EQ(out["scene"], "office.scene.json");
  ASSERT_EQ(out["receivers"].size(), mesh.receivers.size());
  for (size_t i = 0; i < mesh.receivers.size(); ++i) {
    const ReceiverMesh& r = mesh.receivers[i];
    const json& w = out["receivers"][i];
    EXPECT_EQ(w["object"], scene.objects()[r.face.object].id);
    EXPECT_EQ(w["face"], r.face.face);
    EXPECT_EQ(w["positions"].size(), r.positions.size());
    for (size_t k = 0; k < r.classes.size(); ++k) {
      const char* expected = r.classes[k] == LightClass::Lit ? "lit"
                             : r.classes[k] == LightClass::Umbra ? "umbra" : "penumbra";
      EXPECT_EQ(w["class"][k], expected);
    }
    EXPECT_EQ(w["triangles"][0], json::array({r.triangles[0][0], r.triangles[0][1], r.triangles[0][2]}));
  }
  // The floor is the first receiver and faces up.
  EXPECT_EQ(out["receivers"][0]["object"], "floor");
  EXPECT_EQ(out["receivers"][0]["normal"], json::array({0.0, 1.0, 0.0}));
}

TEST_F(MeshJson, RoundTripsExactly) {
  expectSameMesh(mesh, meshFromJson(meshToJson(scene, mesh, "s.json"), scene));
  const std::string text = meshToJson(scene, mesh, "s.json").dump();
  expectSameMesh(mesh, meshFromJson(parseJsonText(text, kMaxJsonFileBytes, kMaxJsonDepth), scene));
}

// The streamed writer (one receiver at a time) writes the document's own compact text, for a
// mesh, an empty one, and a scene name holding invalid UTF-8 (replaced, as dump() does).
TEST_F(MeshJson, StreamedTextIsTheDocumentsText) {
  const auto documentText = [&](const Mesh& m, const std::string& name) {
    return meshToJson(scene, m, name).dump(-1, ' ', false, json::error_handler_t::replace) + "\n";
  };
  for (const std::string& name : {std::string("office.scene.json"), std::string("bad\xff\xfe name")}) {
    for (const Mesh& m : {mesh, Mesh{}}) {
      std::ostringstream streamed;
      writeMeshJson(streamed, scene, m, name);
      EXPECT_EQ(streamed.str(), documentText(m, name)) << name << ", " << m.receivers.size() << " receivers";
    }
  }
}

// The server's answers add members (ids, versions, indirect light): streamed, they are merged
// in key order, replacing a member of the same name, exactly as operator[] on the document.
TEST_F(MeshJson, StreamedExtrasAreTheDocumentsMembers) {
  ASSERT_GE(mesh.receivers.size(), 2u);
  MeshJsonExtras extras;
  extras.root = {{"id", "s1"}, {"scene_version", 7}, {"since", nullptr}, {"removed", json::array()},
                 {"indirect", {{"bounces", 2}}}, {"aaa first", 1}, {"zzz last", "\xff"}, {"scene", "replaced"}};
  extras.receiver = [](size_t k) {
    if (k == 1) return json();  // null: nothing added
    return json{{"scene_version", k}, {"indirect", {{0.5, k, 1e-300}}}, {"face", 99}, {"\x01", true}};
  };
  json document = meshToJson(scene, mesh, "name");
  for (const auto& member : extras.root.items()) document[member.key()] = member.value();
  for (size_t k = 0; k < mesh.receivers.size(); ++k) {
    const json members = extras.receiver(k);
    for (const auto& member : members.items()) document["receivers"][k][member.key()] = member.value();
  }
  std::ostringstream streamed;
  writeMeshJson(streamed, scene, mesh, "name", extras);
  EXPECT_EQ(streamed.str(), document.dump(-1, ' ', false, json::error_handler_t::replace) + "\n");
}

TEST_F(MeshJson, FilesRoundTrip) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("penumbra_protocol_" + std::to_string(::getpid()) + "_mesh.json");
  saveMeshFile(scene, mesh, "base.scene.json", path.string());
  expectSameMesh(mesh, loadMeshFile(path.string(), scene));
  // A file says which bound its mesh meets, and the reader gives it back (a mesh written
  // without the keys, by meshToJson, states nothing: 0).
  Mesh refined = mesh;
  refined.tolerance = 0.0025, refined.cappedCells = 3;
  saveMeshFile(scene, refined, "base.scene.json", path.string());
  const Mesh loaded = loadMeshFile(path.string(), scene);
  EXPECT_EQ(loaded.tolerance, 0.0025);
  EXPECT_EQ(loaded.cappedCells, 3u);
  EXPECT_EQ(meshFromJson(meshToJson(scene, refined, "s"), scene).tolerance, 0);
  std::filesystem::remove(path);
}

TEST_F(MeshJson, WriterRefusesFacesNotInTheScene) {
  Mesh bad = mesh;
  bad.receivers[0].face.face = 5;  // the floor has one face
  EXPECT_THROW((void)meshToJson(scene, bad, "s"), std::out_of_range);
}

struct MeshCase {
  const char* name;
  void (*mutate)(json&);
  const char* path;
  const char* word;
};

class MalformedMesh : public MeshJson, public ::testing::WithParamInterface<MeshCase> {};

TEST_P(MalformedMesh, IsRefusedWithKeyPath) {
  json out = meshToJson(scene, mesh, "s.json");
  GetParam().mutate(out);
  try {
    (void)meshFromJson(out, scene);
    FAIL() << "accepted a malformed mesh";
  } catch (const ValidationError& e) {
    EXPECT_EQ(e.path(), GetParam().path) << e.what();
    EXPECT_NE(e.problem().find(GetParam().word), std::string::npos) << e.what();
  }
}

// receivers[1] is box1's face 0 (-z) in the base scene.
const MeshCase kMeshCases[] = {
    {"WrongFormat", [](json& m) { m["format"] = "penumbra.scene"; }, "format", "penumbra.mesh"},
    {"NegativeTolerance", [](json& m) { m["tolerance"] = -0.01; }, "tolerance", "at least 0"},
    {"TextTolerance", [](json& m) { m["tolerance"] = "0.005"; }, "tolerance", "expected a number"},
    {"NegativeCappedCells", [](json& m) { m["capped_cells"] = -1; }, "capped_cells", "negative"},
    {"WrongVersion", [](json& m) { m["version"] = 3; }, "version", "unsupported version 3"},
    {"MissingScene", [](json& m) { m.erase("scene"); }, "scene", "missing required key"},
    {"ReceiversNotArray", [](json& m) { m["receivers"] = 1; }, "receivers", "expected an array"},
    {"UnknownObject", [](json& m) { m["receivers"][1]["object"] = "box9"; }, "receivers[1].object",
     "unknown object 'box9'"},
    {"FaceOutOfRange", [](json& m) { m["receivers"][1]["face"] = 6; }, "receivers[1].face", "out of range"},
    {"NormalNotUnit", [](json& m) { m["receivers"][1]["normal"] = {0, 0, 2}; }, "receivers[1].normal",
     "unit length"},
    {"PositionNotVector", [](json& m) { m["receivers"][1]["positions"][2] = {1, 2}; },
     "receivers[1].positions[2]", "3 numbers"},
    {"IrradianceShort", [](json& m) { m["receivers"][1]["irradiance"].erase(0); }, "receivers[1].irradiance",
     "positions has"},
    {"IrradianceNegative", [](json& m) { m["receivers"][1]["irradiance"][3][1] = -1; },
     "receivers[1].irradiance[3]", "negative"},
    {"ClassMissing", [](json& m) { m["receivers"][0].erase("class"); }, "receivers[0].class",
     "missing required key"},
    {"UnknownClass", [](json& m) { m["receivers"][1]["class"][2] = "dark"; }, "receivers[1].class[2]",
     "unknown class 'dark'"},
    {"TriangleTwoIndices", [](json& m) { m["receivers"][1]["triangles"][0] = {0, 1}; },
     "receivers[1].triangles[0]", "3 indices"},
    {"TriangleIndexOutOfRange", [](json& m) { m["receivers"][1]["triangles"][1][2] = 5; },
     "receivers[1].triangles[1][2]", "out of range"},
    {"TriangleRepeatsVertex", [](json& m) { m["receivers"][1]["triangles"][1] = {0, 0, 4}; },
     "receivers[1].triangles[1]", "repeats"},
};

INSTANTIATE_TEST_SUITE_P(Cases, MalformedMesh, ::testing::ValuesIn(kMeshCases),
                         [](const ::testing::TestParamInfo<MeshCase>& info) { return info.param.name; });

}  // namespace
}  // namespace penumbra::protocol
