// GLB export read back with tinygltf: one mesh per object and per light, counts, bounds,
// COLOR_0 = the page's display colour in [0, 1], the exact _RADIANCE and _IRRADIANCE, emissive
// lights and the camera (issue 40; the Khronos validator runs in gltf_validate.mjs).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>

#include <glm/gtc/quaternion.hpp>
#include <tiny_gltf.h>

#include "core/engine/engine.h"
#include "interchange/dm_edges.h"
#include "interchange/glb_export.h"
#include "interchange_fixtures.h"
#include "protocol/scene_json.h"

namespace penumbra::interchange {
namespace {

using testing::runPenumbra;
using testing::scratchDir;

const std::string kCornell = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell.scene.json";

tinygltf::Model readGlb(const std::vector<uint8_t>& bytes) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  EXPECT_TRUE(loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), unsigned(bytes.size()))) << err;
  return model;
}

// An accessor's floats (tightly packed VEC3/SCALAR float, as the exporter writes).
std::vector<float> floats(const tinygltf::Model& model, int index) {
  const tinygltf::Accessor& a = model.accessors[size_t(index)];
  EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  const tinygltf::BufferView& view = model.bufferViews[size_t(a.bufferView)];
  const size_t n = a.count * size_t(tinygltf::GetNumComponentsInType(uint32_t(a.type)));
  std::vector<float> out(n);
  std::memcpy(out.data(), model.buffers[size_t(view.buffer)].data.data() + view.byteOffset + a.byteOffset, n * 4);
  return out;
}

std::vector<uint32_t> indices(const tinygltf::Model& model, int index) {
  const tinygltf::Accessor& a = model.accessors[size_t(index)];
  EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
  const tinygltf::BufferView& view = model.bufferViews[size_t(a.bufferView)];
  std::vector<uint32_t> out(a.count);
  std::memcpy(out.data(), model.buffers[size_t(view.buffer)].data.data() + view.byteOffset + a.byteOffset, a.count * 4);
  return out;
}

// Ambient fill as the page computes it (web_client/src/tone_map.js), written out again here
// rather than taken from the exporter's helper.
Vec3 pageAmbient(const Scene& scene) {
  Vec3 power(0.0);
  for (const Light& light : scene.lights()) power += M_PI * light.radiance * light.area();
  const Vec3 e = scene.bounds().max - scene.bounds().min;
  return 0.1 * power / (2 * (e.x * e.y + e.y * e.z + e.z * e.x));
}

void expectColour(const std::vector<float>& colors, size_t v, const Vec3& expected) {
  for (int c = 0; c < 3; ++c)
    EXPECT_FLOAT_EQ(colors[v * 3 + size_t(c)], float(std::min(1.0, expected[c]))) << "vertex " << v << " channel " << c;
}

TEST(GlbExport, ColoursAreThePagesExposureAndTheExactValuesRideAlong) {
  const Scene scene = protocol::loadSceneFile(kCornell);
  Engine engine(scene);
  const Mesh mesh = engine.mesh();
  const GlbFile glb = meshToGlb(engine.scene(), mesh);
  const tinygltf::Model model = readGlb(glb.bytes);

  EXPECT_EQ(model.asset.version, "2.0");
  EXPECT_NE(std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(), "KHR_materials_unlit"),
            model.extensionsUsed.end());
  ASSERT_FALSE(model.materials.empty());
  EXPECT_TRUE(model.materials[0].extensions.count("KHR_materials_unlit"));
  const double scale = model.asset.extras.Get("penumbra").Get("color_scale").GetNumberAsDouble();
  EXPECT_EQ(scale, glb.colorScale);
  const Vec3 ambient = pageAmbient(scene);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(glb.ambient[c], ambient[c], 1e-12 * ambient[c]);

  // One mesh per object (every object here has faces) plus one per light.
  ASSERT_EQ(model.meshes.size(), scene.objects().size() + scene.lights().size());
  EXPECT_EQ(glb.meshes, model.meshes.size());
  size_t totalVertices = 0, clamped = 0, receiverVertices = 0;
  for (size_t i = 0; i < scene.objects().size(); ++i) {
    const uint32_t handle = scene.handleOf(i);
    const tinygltf::Mesh& m = model.meshes[i];
    EXPECT_EQ(m.name, scene.objects()[i].id);
    ASSERT_EQ(m.primitives.size(), 1u);
    const tinygltf::Primitive& primitive = m.primitives[0];
    EXPECT_EQ(primitive.mode, TINYGLTF_MODE_TRIANGLES);
    const std::vector<float> positions = floats(model, primitive.attributes.at("POSITION"));
    const std::vector<float> colors = floats(model, primitive.attributes.at("COLOR_0"));
    const std::vector<float> radiance = floats(model, primitive.attributes.at("_RADIANCE"));
    const std::vector<float> irradiance = floats(model, primitive.attributes.at("_IRRADIANCE"));
    const std::vector<uint32_t> triangles = indices(model, primitive.indices);
    ASSERT_EQ(colors.size(), positions.size());
    ASSERT_EQ(radiance.size(), positions.size());
    ASSERT_EQ(irradiance.size(), positions.size());
    for (float c : colors) EXPECT_TRUE(c >= 0 && c <= 1) << "COLOR_0 must lie in [0, 1], got " << c;

    // Expected: the receivers' vertices in mesh order, then the dark faces (the fill only).
    size_t v = 0, expectedTriangles = 0;
    for (const ReceiverMesh& r : mesh.receivers) {
      if (r.face.object != handle) continue;
      const Vec3 albedo = scene.albedo(r.face);
      for (size_t k = 0; k < r.positions.size(); ++k, ++v) {
        const Vec3 exact = albedo / M_PI * r.irradiance[k], shown = scale * (exact + albedo / M_PI * ambient);
        for (int c = 0; c < 3; ++c) {
          EXPECT_FLOAT_EQ(positions[v * 3 + size_t(c)], float(r.positions[k][c]));
          EXPECT_FLOAT_EQ(radiance[v * 3 + size_t(c)], float(exact[c]));
          EXPECT_FLOAT_EQ(irradiance[v * 3 + size_t(c)], float(r.irradiance[k][c]));
        }
        expectColour(colors, v, shown);
        clamped += std::max({shown.x, shown.y, shown.z}) > 1 ? 1 : 0;
        ++receiverVertices;
      }
      expectedTriangles += r.triangles.size();
    }
    for (; v < colors.size() / 3; ++v) {
      expectColour(colors, v, scale * scene.albedo(FaceId{handle, 0}) / M_PI * ambient);  // one material an object
      EXPECT_EQ(radiance[v * 3], 0.0f) << "a face that receives no light has no exact radiance";
    }
    EXPECT_GE(triangles.size() / 3, expectedTriangles);
    for (uint32_t index : triangles) EXPECT_LT(index, positions.size() / 3);
    totalVertices += positions.size() / 3;

    // POSITION carries its bounds, and they are the positions' bounds.
    const tinygltf::Accessor& accessor = model.accessors[size_t(primitive.attributes.at("POSITION"))];
    ASSERT_EQ(accessor.minValues.size(), 3u);
    for (int c = 0; c < 3; ++c) {
      float lo = INFINITY, hi = -INFINITY;
      for (size_t k = 0; k < positions.size() / 3; ++k) {
        lo = std::min(lo, positions[k * 3 + size_t(c)]);
        hi = std::max(hi, positions[k * 3 + size_t(c)]);
      }
      EXPECT_EQ(accessor.minValues[size_t(c)], lo);
      EXPECT_EQ(accessor.maxValues[size_t(c)], hi);
    }
  }
  EXPECT_EQ(totalVertices, glb.vertices);
  EXPECT_GE(totalVertices, mesh.vertexCount());
  // The page's exposure: the 99th percentile is shown at 1, so about 1 % of vertices clip.
  EXPECT_GT(clamped, 0u);
  EXPECT_LE(double(clamped), 0.011 * double(receiverVertices) + 1);

  // The light: its own mesh and node, emitting radiance × scale (factor × strength), no COLOR_0.
  const Light& light = scene.lights()[0];
  const tinygltf::Mesh& lightMesh = model.meshes[scene.objects().size()];
  EXPECT_EQ(lightMesh.name, light.id);
  EXPECT_FALSE(lightMesh.primitives[0].attributes.count("COLOR_0"));
  const tinygltf::Material& emitting = model.materials[size_t(lightMesh.primitives[0].material)];
  const double strength = emitting.extensions.count("KHR_materials_emissive_strength")
                              ? emitting.extensions.at("KHR_materials_emissive_strength").Get("emissiveStrength").GetNumberAsDouble()
                              : 1.0;
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(emitting.emissiveFactor[size_t(c)], 1.0);
    EXPECT_NEAR(emitting.emissiveFactor[size_t(c)] * strength, light.radiance[c] * scale, 1e-9 * light.radiance[c] * scale);
  }

  // The scene's camera (or the default view) as a camera node looking at its target.
  const auto camera = std::find_if(model.nodes.begin(), model.nodes.end(), [](const tinygltf::Node& n) { return n.camera >= 0; });
  ASSERT_NE(camera, model.nodes.end());
  ASSERT_EQ(camera->rotation.size(), 4u);
  const glm::dquat q(camera->rotation[3], camera->rotation[0], camera->rotation[1], camera->rotation[2]);
  const Vec3 eye(camera->translation[0], camera->translation[1], camera->translation[2]);
  const Camera expected = scene.camera() ? *scene.camera() : Camera{};
  if (scene.camera()) {
    const Vec3 looking = q * Vec3(0, 0, -1), towards = glm::normalize(expected.target - expected.position);
    EXPECT_NEAR(glm::dot(looking, towards), 1.0, 1e-12);
    EXPECT_NEAR(glm::length(eye - expected.position), 0.0, 1e-12);
  }
}

TEST(GlbExport, ExplicitScaleAndDiscontinuityLines) {
  const Scene scene = protocol::loadSceneFile(kCornell);
  Engine engine(scene);
  const Mesh mesh = engine.mesh();
  GlbOptions options;
  options.colorScale = 0.25;
  options.lights = false;
  options.edges = dmEdges(engine);
  ASSERT_FALSE(options.edges.empty());
  const GlbFile glb = meshToGlb(engine.scene(), mesh, options);
  const tinygltf::Model model = readGlb(glb.bytes);
  ASSERT_EQ(model.meshes.size(), scene.objects().size() + 1);
  const tinygltf::Mesh& lines = model.meshes.back();
  EXPECT_EQ(lines.name, "discontinuities");
  EXPECT_EQ(lines.primitives[0].mode, TINYGLTF_MODE_LINE);
  EXPECT_EQ(model.accessors[size_t(lines.primitives[0].attributes.at("POSITION"))].count, options.edges.size() * 2);
  const ReceiverMesh& first = mesh.receivers[0];
  const std::vector<float> colors = floats(model, model.meshes[0].primitives[0].attributes.at("COLOR_0"));
  ASSERT_EQ(first.face.object, scene.handleOf(0));
  const Vec3 albedo = scene.albedo(first.face);
  expectColour(colors, 0, 0.25 * albedo / M_PI * (first.irradiance[0] + glb.ambient));
}

// GlbOptions::indirect: the indirect irradiance replaces the fill in COLOR_0 and is added to
// _RADIANCE (not to _IRRADIANCE, the exact direct light), flagged in the extras.
TEST(GlbExport, IndirectIrradianceReplacesTheFill) {
  const Scene scene = protocol::loadSceneFile(kCornell);
  Engine engine(scene);
  const Mesh mesh = engine.mesh();
  Mesh indirect = mesh;
  for (ReceiverMesh& r : indirect.receivers)
    for (Vec3& e : r.irradiance) e = Vec3(0.01, 0.02, 0.03);
  GlbOptions options;
  options.colorScale = 0.25;
  options.indirect = &indirect;
  const tinygltf::Model model = readGlb(meshToGlb(engine.scene(), mesh, options).bytes);
  EXPECT_TRUE(model.asset.extras.Get("penumbra").Get("indirect").Get<bool>());
  const ReceiverMesh& first = mesh.receivers[0];
  ASSERT_EQ(first.face.object, scene.handleOf(0));
  const tinygltf::Primitive& primitive = model.meshes[0].primitives[0];
  const std::vector<float> colors = floats(model, primitive.attributes.at("COLOR_0"));
  const std::vector<float> radiance = floats(model, primitive.attributes.at("_RADIANCE"));
  const std::vector<float> irradiance = floats(model, primitive.attributes.at("_IRRADIANCE"));
  const Vec3 e = first.irradiance[0] + Vec3(0.01, 0.02, 0.03), albedo = scene.albedo(first.face);
  expectColour(colors, 0, 0.25 * albedo / M_PI * e);
  for (int c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(radiance[size_t(c)], float(albedo[c] / M_PI * e[c]));
    EXPECT_FLOAT_EQ(irradiance[size_t(c)], float(first.irradiance[0][c]));
  }
  Mesh wrongShape = mesh;
  wrongShape.receivers.pop_back();
  options.indirect = &wrongShape;
  EXPECT_THROW(meshToGlb(engine.scene(), mesh, options), std::invalid_argument);
}

TEST(GlbExport, BuildCommandWritesIndirectGlb) {
  const auto dir = scratchDir();
  const std::string out = (dir / "cornell_gi.glb").string();
  ASSERT_EQ(runPenumbra("build " + kCornell + " --out " + out + " --indirect --sensor-size 4", dir / "build"), 0);
  std::ifstream in(out, std::ios::binary);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(readGlb(bytes).asset.extras.Get("penumbra").Get("indirect").Get<bool>());
  EXPECT_NE(runPenumbra("build " + kCornell + " --out " + out + " --sensor-size 4", dir / "build2"), 0);
}

TEST(GlbExport, BuildCommandWritesGlbByExtension) {
  const auto dir = scratchDir();
  const std::string out = (dir / "cornell.glb").string();
  ASSERT_EQ(runPenumbra("build " + kCornell + " --out " + out + " --edges", dir / "build"), 0);
  std::ifstream in(out, std::ios::binary);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GE(bytes.size(), 12u);
  EXPECT_EQ(std::memcmp(bytes.data(), "glTF", 4), 0);
  const tinygltf::Model model = readGlb(bytes);
  EXPECT_EQ(model.meshes.back().name, "discontinuities");
}

}  // namespace
}  // namespace penumbra::interchange
