// glTF/GLB import: meshes → objects (node transforms applied, triangles joined
// back into convex faces), baseColorFactor → albedo, emissiveFactor ×
// KHR_materials_emissive_strength → lights. The test writes its glTF with tinygltf.
#include <gtest/gtest.h>

#include <cmath>

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include <tiny_gltf.h>

#include "interchange/gltf_import.h"
#include "interchange/scene_import.h"
#include "interchange_fixtures.h"
#include "gltf_model_writer.h"
#include "protocol/validation_error.h"

namespace penumbra::interchange {
namespace {

using testing::scratchDir;
using testing::writeFile;

std::vector<uint8_t> smallModel(bool binary) {
  ModelWriter w;
  const int grey = w.material("grey", {0.5, 0.6, 0.7}, {0, 0, 0}, 1);
  const int lamp = w.material("lamp", {1, 1, 1}, {1, 0.5, 0.25}, 8);
  w.quad("floor", {{{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}}}, grey, {0, 0, 0});
  w.quad("card", {{{-0.5, 0, -0.5}, {-0.5, 0, 0.5}, {0.5, 0, 0.5}, {0.5, 0, -0.5}}}, grey, {0, 1, 0});
  // Wound facing up: the importer turns it down towards the scene, and says so.
  w.quad("lamp", {{{-0.5, 0, -0.5}, {-0.5, 0, 0.5}, {0.5, 0, 0.5}, {0.5, 0, -0.5}}}, lamp, {0, 3, 0});
  return w.write(binary);
}

void expectSmallScene(const ImportResult& result) {
  const Scene& scene = result.scene;
  // The floor's and the card's two triangles are one face each again; the lamp's one light.
  EXPECT_EQ(result.report.repaired("coplanar_triangles_joined"), 2u) << result.report.summary();
  EXPECT_EQ(result.report.repaired("coplanar_light_triangles_joined"), 1u);
  EXPECT_EQ(result.report.repaired("lights_turned_to_face_the_scene"), 1u);
  ASSERT_EQ(scene.lights().size(), 1u);
  EXPECT_EQ(scene.lights()[0].polygon.size(), 4u);
  EXPECT_EQ(scene.lights()[0].radiance, Vec3(8, 4, 2));
  for (const Vec3& p : scene.lights()[0].polygon) EXPECT_EQ(p.y, 3);
  ASSERT_EQ(scene.objects().size(), 2u);
  EXPECT_EQ(scene.faces().size(), 2u);  // each quad's two triangles are one face again
  const auto card = scene.findObject("card");
  ASSERT_TRUE(card);
  for (const Vec3& v : scene.objects()[*card].vertices) EXPECT_EQ(v.y, 1);  // node translation applied
  EXPECT_EQ(scene.albedo(scene.faces()[0].id), Vec3(0.5, 0.6, 0.7));
}

TEST(GltfImport, GlbFromMemory) {
  const ImportResult result = importSceneBytes(smallModel(true), "small.glb", {}, {});
  EXPECT_EQ(result.report.format, "glb");
  expectSmallScene(result);
}

TEST(GltfImport, GltfFileWithEmbeddedBuffer) {
  const auto dir = scratchDir();
  const std::vector<uint8_t> text = smallModel(false);
  writeFile(dir / "small.gltf", std::string(text.begin(), text.end()));
  const ImportResult result = importGltfFile((dir / "small.gltf").string(), {});
  EXPECT_EQ(result.report.format, "gltf");
  expectSmallScene(result);
}

// A lamp folded along its diagonal is two lights, each a triangle (coplanar ones join above).
TEST(GltfImport, FoldedLampStaysTwoLights) {
  ModelWriter w;
  const int grey = w.material("grey", {0.5, 0.6, 0.7}, {0, 0, 0}, 1);
  const int lamp = w.material("lamp", {1, 1, 1}, {1, 0.5, 0.25}, 8);
  w.quad("floor", {{{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}}}, grey, {0, 0, 0});
  w.quad("lamp", {{{-0.5, 0, -0.5}, {0.5, 0, -0.5}, {0.5, 0, 0.5}, {-0.5, 0.2, 0.5}}}, lamp, {0, 3, 0});
  const ImportResult result = importSceneBytes(w.write(true), "folded.glb", {}, {});
  EXPECT_EQ(result.report.repaired("coplanar_light_triangles_joined"), 0u) << result.report.summary();
  ASSERT_EQ(result.scene.lights().size(), 2u);
  for (const Light& light : result.scene.lights()) {
    EXPECT_EQ(light.polygon.size(), 3u);
    EXPECT_EQ(light.radiance, Vec3(8, 4, 2));
  }
}

// A GLB with no emissive material goes into the default studio like an OBJ: scaled to fit (its
// 40-unit card is 1 m), resting on the floor; studio = false refuses it.
TEST(GltfImport, ModelWithoutLightsGoesIntoTheDefaultStudio) {
  ModelWriter w;
  const int grey = w.material("grey", {0.5, 0.6, 0.7}, {0, 0, 0}, 1);
  w.quad("card", {{{-20, -20, 0}, {20, -20, 0}, {20, 20, 0}, {-20, 20, 0}}}, grey, {0, 7, 0});  // standing
  const std::vector<uint8_t> glb = w.write(true);
  const ImportResult result = importSceneBytes(glb, "card.glb", {}, {});
  ASSERT_TRUE(result.report.studio) << result.report.summary();
  EXPECT_EQ(result.report.studio->scale, 1.0 / 40);
  EXPECT_NE(result.report.studio->sentence.find("no lights in card.glb"), std::string::npos);
  ASSERT_EQ(result.scene.lights().size(), 1u);
  const auto card = result.scene.findObject("card");
  ASSERT_TRUE(card);
  double lowest = INFINITY;
  for (const Vec3& v : result.scene.objects()[*card].vertices) {
    lowest = std::min(lowest, v.y);
    EXPECT_LE(std::abs(v.x), 0.5 + 1e-12);
    EXPECT_LE(v.y, 1 + 1e-12);
  }
  EXPECT_EQ(lowest, 0);  // standing on the floor
  ASSERT_EQ(result.report.meshes.size(), 1u);
  EXPECT_EQ(result.report.meshes[0].components, 1u);  // its two triangles joined into one face
  ImportOptions noStudio;
  noStudio.studio = false;
  EXPECT_THROW(importSceneBytes(glb, "card.glb", {}, noStudio), protocol::ValidationError);
}

TEST(GltfImport, UploadsCannotReadFilesAndBadAccessorsAreErrors) {
  const std::string external =
      R"({"asset":{"version":"2.0"},"buffers":[{"uri":"/etc/passwd","byteLength":12}],)"
      R"("bufferViews":[{"buffer":0,"byteLength":12}],)"
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":1,"type":"VEC3"}],)"
      R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]})";
  EXPECT_THROW(importSceneBytes(std::vector<uint8_t>(external.begin(), external.end()), "x.gltf", {}, {}),
               protocol::ValidationError);
  const std::string overrun =
      R"({"asset":{"version":"2.0"},"buffers":[{"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAA","byteLength":12}],)"
      R"("bufferViews":[{"buffer":0,"byteLength":12}],)"
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],)"
      R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]})";
  try {
    importSceneBytes(std::vector<uint8_t>(overrun.begin(), overrun.end()), "x.gltf", {}, {});
    FAIL() << "an accessor past its buffer view was accepted";
  } catch (const protocol::ValidationError& error) {
    EXPECT_EQ(error.path(), "meshes[0].primitives[0].attributes.POSITION") << error.what();
  }
}

}  // namespace
}  // namespace penumbra::interchange

namespace penumbra::interchange {
namespace {

// Found by the gltf_import fuzz target: a NaN position reached the welding grid (UB).
TEST(GltfImport, NonFiniteCoordinatesAreRefusedWithTheirPath) {
  const std::string path =
      std::string(PENUMBRA_SOURCE_DIR) + "/tests/fuzz/crashes/gltf_import/weld-nan-position.gltf";
  std::ifstream in(path, std::ios::binary);
  ASSERT_TRUE(in) << path;
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::vector<uint8_t> bytes(text.begin(), text.end());
  try {
    importSceneBytes(bytes, "weld-nan-position.gltf", {}, {});
    FAIL() << "a NaN position was imported";
  } catch (const protocol::ValidationError& error) {
    EXPECT_NE(error.path().find(".positions["), std::string::npos) << error.path();
  }
}

}  // namespace
}  // namespace penumbra::interchange

namespace penumbra::interchange {
namespace {

// pbrMetallicRoughness, KHR_materials_transmission and KHR_materials_ior onto material types.
TEST(GltfImport, PbrMaterialsMapOntoMicrofacetTypes) {
  ModelWriter w;
  const int metal = w.material("metal", {0.9, 0.6, 0.3}, {0, 0, 0}, 1);  // metallicFactor: default 1
  const int plastic = w.material("plastic", {0.5, 0.5, 0.5}, {0, 0, 0}, 1);
  const int glass = w.material("glass", {1, 1, 1}, {0, 0, 0}, 1);
  const int lamp = w.material("lamp", {1, 1, 1}, {1, 1, 1}, 8);
  tinygltf::Model& model = w.model();
  model.materials[size_t(metal)].pbrMetallicRoughness.roughnessFactor = 0.5;
  model.materials[size_t(plastic)].pbrMetallicRoughness.metallicFactor = 0;
  model.materials[size_t(glass)].pbrMetallicRoughness.metallicFactor = 0;
  model.materials[size_t(glass)].pbrMetallicRoughness.roughnessFactor = 0.1;
  model.materials[size_t(glass)].extensions["KHR_materials_transmission"] =
      tinygltf::Value(tinygltf::Value::Object{{"transmissionFactor", tinygltf::Value(1.0)}});
  model.materials[size_t(glass)].extensions["KHR_materials_ior"] =
      tinygltf::Value(tinygltf::Value::Object{{"ior", tinygltf::Value(1.33)}});
  model.materials[size_t(lamp)].pbrMetallicRoughness.metallicFactor = 0;
  const std::array<Vec3, 4> quad = {{{-0.5, 0, -0.5}, {-0.5, 0, 0.5}, {0.5, 0, 0.5}, {0.5, 0, -0.5}}};
  w.quad("a", quad, metal, {0, 0, 0});
  w.quad("b", quad, plastic, {0, 1, 0});
  w.quad("c", quad, glass, {0, 2, 0});
  w.quad("lamp", quad, lamp, {0, 3, 0});
  const ImportResult result = importSceneBytes(w.write(true), "m.glb", {}, {});
  const Scene& scene = result.scene;
  const Material& m = scene.materials()[*scene.findMaterial("metal")];
  EXPECT_EQ(m.type, MaterialType::Conductor);
  EXPECT_DOUBLE_EQ(m.roughness.x, 0.25);
  for (int c = 0; c < 3; ++c)  // normal-incidence reflectance of eta + ik is the base colour
    EXPECT_NEAR((std::pow(m.eta[c] - 1, 2) + m.k[c] * m.k[c]) / (std::pow(m.eta[c] + 1, 2) + m.k[c] * m.k[c]),
                m.albedo[c], 1e-6);
  EXPECT_EQ(scene.materials()[*scene.findMaterial("plastic")].type, MaterialType::Diffuse);
  const Material& g = scene.materials()[*scene.findMaterial("glass")];
  EXPECT_EQ(g.type, MaterialType::Dielectric);
  EXPECT_DOUBLE_EQ(g.ior, 1.33);
  EXPECT_NEAR(g.roughness.x, 0.01, 1e-12);
  EXPECT_EQ(result.report.repaired("materials_mapped_to_conductor"), 1u) << result.report.summary();
  EXPECT_EQ(result.report.repaired("materials_mapped_to_dielectric"), 1u);
}

}  // namespace
}  // namespace penumbra::interchange

namespace penumbra::interchange {
namespace {

// The rules' edges: glTF's default roughnessFactor (1) and metallicFactor (1), transmission
// before metallic, below-half factors staying diffuse, a missing or impossible ior, unlit.
TEST(GltfImport, PbrMappingEdges) {
  ModelWriter w;
  const int rough = w.material("rough_metal", {0.8, 0.8, 0.8}, {0, 0, 0}, 1);  // factors at their defaults
  const int both = w.material("metal_glass", {1, 1, 1}, {0, 0, 0}, 1);
  const int weak = w.material("weak", {0.5, 0.5, 0.5}, {0, 0, 0}, 1);
  const int noIor = w.material("no_ior", {1, 1, 1}, {0, 0, 0}, 1);
  const int badIor = w.material("bad_ior", {1, 1, 1}, {0, 0, 0}, 1);
  const int unlit = w.material("unlit", {0.5, 0.5, 0.5}, {0, 0, 0}, 1);
  const int lamp = w.material("lamp", {1, 1, 1}, {1, 1, 1}, 8);
  tinygltf::Model& model = w.model();
  auto transmit = [&](int m, double factor) {
    model.materials[size_t(m)].extensions["KHR_materials_transmission"] =
        tinygltf::Value(tinygltf::Value::Object{{"transmissionFactor", tinygltf::Value(factor)}});
  };
  transmit(both, 1);
  model.materials[size_t(weak)].pbrMetallicRoughness.metallicFactor = 0.4;
  transmit(weak, 0.4);
  model.materials[size_t(noIor)].pbrMetallicRoughness.metallicFactor = 0;
  transmit(noIor, 0.9);
  model.materials[size_t(badIor)].pbrMetallicRoughness.metallicFactor = 0;
  transmit(badIor, 1);
  model.materials[size_t(badIor)].extensions["KHR_materials_ior"] =
      tinygltf::Value(tinygltf::Value::Object{{"ior", tinygltf::Value(0.8)}});
  model.materials[size_t(unlit)].extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object{});
  model.materials[size_t(lamp)].pbrMetallicRoughness.metallicFactor = 0;
  const std::array<Vec3, 4> quad = {{{-0.5, 0, -0.5}, {-0.5, 0, 0.5}, {0.5, 0, 0.5}, {0.5, 0, -0.5}}};
  int y = 0;
  for (int m : {rough, both, weak, noIor, badIor, unlit}) w.quad("q" + std::to_string(m), quad, m, {0, double(y++), 0});
  w.quad("lamp", quad, lamp, {0, double(y), 0});
  const ImportResult result = importSceneBytes(w.write(true), "edges.glb", {}, {});
  const Scene& scene = result.scene;
  auto material = [&](const char* name) { return scene.materials()[*scene.findMaterial(name)]; };
  EXPECT_EQ(material("rough_metal").type, MaterialType::Conductor);
  EXPECT_DOUBLE_EQ(material("rough_metal").roughness.x, 1.0);  // roughnessFactor 1 → α 1
  EXPECT_EQ(material("metal_glass").type, MaterialType::Dielectric);  // transmission first
  EXPECT_DOUBLE_EQ(material("metal_glass").ior, 1.5);
  EXPECT_EQ(material("weak").type, MaterialType::Diffuse);
  EXPECT_EQ(material("no_ior").type, MaterialType::Dielectric);
  EXPECT_DOUBLE_EQ(material("no_ior").ior, 1.5);
  EXPECT_DOUBLE_EQ(material("bad_ior").ior, 1.5);  // an ior ≤ 1 would not refract: the default
  EXPECT_EQ(material("unlit").type, MaterialType::Diffuse);
  EXPECT_EQ(result.report.repaired("materials_mapped_to_dielectric"), 3u) << result.report.summary();
  EXPECT_EQ(result.report.repaired("materials_mapped_to_conductor"), 1u);
}

// Node transforms compose down the hierarchy (parent × child: translation, rotation, scale), and
// of several scenes only the default one is imported.
TEST(GltfImport, NodeHierarchyIsAppliedAndTheDefaultSceneChosen) {
  ModelWriter w;
  const int grey = w.material("grey", {0.5, 0.6, 0.7}, {0, 0, 0}, 1);
  const int lamp = w.material("lamp", {1, 1, 1}, {1, 1, 1}, 8);
  w.quad("floor", {{{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}}}, grey, {0, 0, 0});
  w.quad("lamp", {{{-0.5, 0, -0.5}, {0.5, 0, -0.5}, {0.5, 0, 0.5}, {-0.5, 0, 0.5}}}, lamp, {0, 3, 0});
  w.quad("card", {{{-0.5, 0, -0.5}, {-0.5, 0, 0.5}, {0.5, 0, 0.5}, {0.5, 0, -0.5}}}, grey, {0, 0, 0});
  w.quad("decoy", {{{-0.5, 0, -0.5}, {-0.5, 0, 0.5}, {0.5, 0, 0.5}, {0.5, 0, -0.5}}}, grey, {0, 1, 0});
  tinygltf::Model& model = w.model();
  // The card turned 90° about z (into the plane x = 0) under a parent that scales by 2 and
  // moves by (1, 1, 0): x = 1, y in [0, 2], z in [-1, 1].
  model.nodes[2].translation.clear();
  model.nodes[2].rotation = {0, 0, std::sin(M_PI / 4), std::cos(M_PI / 4)};
  tinygltf::Node parent;
  parent.name = "parent";
  parent.translation = {1, 1, 0};
  parent.scale = {2, 2, 2};
  parent.children = {2};
  model.nodes.push_back(parent);
  model.scenes[0].nodes = {0, 1, 3};  // floor, lamp, decoy
  model.scenes.emplace_back();
  model.scenes[1].nodes = {0, 1, 4};  // floor, lamp, parent → card
  model.defaultScene = 1;
  const ImportResult result = importSceneBytes(w.write(true), "hierarchy.glb", {}, {});
  EXPECT_FALSE(result.scene.findObject("decoy"));
  const auto card = result.scene.findObject("card");
  ASSERT_TRUE(card);
  Vec3 low(INFINITY), high(-INFINITY);
  for (const Vec3& v : result.scene.objects()[*card].vertices) low = glm::min(low, v), high = glm::max(high, v);
  const Vec3 expectedLow(1, 0, -1), expectedHigh(1, 2, 1);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(low[c], expectedLow[c], 1e-6) << c;
    EXPECT_NEAR(high[c], expectedHigh[c], 1e-6) << c;
  }
}

}  // namespace
}  // namespace penumbra::interchange
