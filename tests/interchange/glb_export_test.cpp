// GLB export read back with tinygltf: one mesh per object plus the lights, counts,
// bounds, and COLOR_0 = albedo/π × irradiance × the documented colour scale.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>

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

TEST(GlbExport, ReadBackGivesTheMeshVerticesAndColoursTimesTheScale) {
  const Scene scene = protocol::loadSceneFile(kCornell);
  Engine engine(scene);
  const Mesh mesh = engine.mesh();
  const GlbFile glb = meshToGlb(engine.scene(), mesh);
  const tinygltf::Model model = readGlb(glb.bytes);

  EXPECT_EQ(model.asset.version, "2.0");
  ASSERT_EQ(model.extensionsUsed.size(), 1u);
  EXPECT_EQ(model.extensionsUsed[0], "KHR_materials_unlit");
  ASSERT_FALSE(model.materials.empty());
  EXPECT_TRUE(model.materials[0].extensions.count("KHR_materials_unlit"));
  const double scale = model.asset.extras.Get("penumbra").Get("color_scale").GetNumberAsDouble();
  EXPECT_EQ(scale, glb.colorScale);

  // One mesh per object (every object here has faces) plus "lights".
  ASSERT_EQ(model.meshes.size(), scene.objects().size() + 1);
  EXPECT_EQ(glb.meshes, model.meshes.size());
  double brightest = 0;
  size_t totalVertices = 0;
  for (size_t i = 0; i < scene.objects().size(); ++i) {
    const uint32_t handle = scene.handleOf(i);
    const tinygltf::Mesh& m = model.meshes[i];
    EXPECT_EQ(m.name, scene.objects()[i].id);
    ASSERT_EQ(m.primitives.size(), 1u);
    const tinygltf::Primitive& primitive = m.primitives[0];
    EXPECT_EQ(primitive.mode, TINYGLTF_MODE_TRIANGLES);
    const std::vector<float> positions = floats(model, primitive.attributes.at("POSITION"));
    const std::vector<float> colors = floats(model, primitive.attributes.at("COLOR_0"));
    const std::vector<uint32_t> triangles = indices(model, primitive.indices);

    // Expected: the receivers' vertices in mesh order, then the dark faces.
    std::vector<Vec3> expectedPositions, expectedColors;
    size_t expectedTriangles = 0;
    for (const ReceiverMesh& r : mesh.receivers) {
      if (r.face.object != handle) continue;
      for (size_t v = 0; v < r.positions.size(); ++v) {
        expectedPositions.push_back(r.positions[v]);
        expectedColors.push_back(scene.albedo(r.face) / M_PI * r.irradiance[v] * scale);
      }
      expectedTriangles += r.triangles.size();
    }
    ASSERT_GE(positions.size(), expectedPositions.size() * 3);
    for (size_t v = 0; v < expectedPositions.size(); ++v)
      for (int c = 0; c < 3; ++c) {
        EXPECT_FLOAT_EQ(positions[v * 3 + size_t(c)], float(expectedPositions[v][c]));
        EXPECT_FLOAT_EQ(colors[v * 3 + size_t(c)], float(expectedColors[v][c]));
        brightest = std::max(brightest, double(colors[v * 3 + size_t(c)]));
      }
    for (size_t v = expectedPositions.size(); v < colors.size() / 3; ++v)
      EXPECT_EQ(colors[v * 3], 0.0f) << "a face that receives no light is black";
    EXPECT_GE(triangles.size() / 3, expectedTriangles);
    for (uint32_t index : triangles) EXPECT_LT(index, positions.size() / 3);
    totalVertices += positions.size() / 3;

    // POSITION carries its bounds, and they are the positions' bounds.
    const tinygltf::Accessor& accessor = model.accessors[size_t(primitive.attributes.at("POSITION"))];
    ASSERT_EQ(accessor.minValues.size(), 3u);
    for (int c = 0; c < 3; ++c) {
      float lo = INFINITY, hi = -INFINITY;
      for (size_t v = 0; v < positions.size() / 3; ++v) {
        lo = std::min(lo, positions[v * 3 + size_t(c)]);
        hi = std::max(hi, positions[v * 3 + size_t(c)]);
      }
      EXPECT_EQ(accessor.minValues[size_t(c)], lo);
      EXPECT_EQ(accessor.maxValues[size_t(c)], hi);
    }
  }
  EXPECT_EQ(totalVertices, glb.vertices);
  EXPECT_FLOAT_EQ(float(brightest), 1.0f) << "default scale: the brightest vertex is 1";
  EXPECT_GE(totalVertices, mesh.vertexCount());

  const tinygltf::Mesh& lights = model.meshes.back();
  EXPECT_EQ(lights.name, "lights");
  const std::vector<float> lightColors = floats(model, lights.primitives[0].attributes.at("COLOR_0"));
  EXPECT_FLOAT_EQ(lightColors[0], float(scene.lights()[0].radiance.x * scale));
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
  const tinygltf::Model model = readGlb(meshToGlb(engine.scene(), mesh, options).bytes);
  ASSERT_EQ(model.meshes.size(), scene.objects().size() + 1);
  const tinygltf::Mesh& lines = model.meshes.back();
  EXPECT_EQ(lines.name, "discontinuities");
  EXPECT_EQ(lines.primitives[0].mode, TINYGLTF_MODE_LINE);
  EXPECT_EQ(model.accessors[size_t(lines.primitives[0].attributes.at("POSITION"))].count, options.edges.size() * 2);
  const ReceiverMesh& first = mesh.receivers[0];
  const std::vector<float> colors = floats(model, model.meshes[0].primitives[0].attributes.at("COLOR_0"));
  if (first.face.object == scene.handleOf(0)) {
    EXPECT_FLOAT_EQ(colors[0], float(scene.albedo(first.face).x / M_PI * first.irradiance[0].x * 0.25));
  }
}

// GlbOptions::indirect: COLOR_0 = albedo/π × (E_direct + E_indirect) × scale, flagged in the extras.
TEST(GlbExport, IndirectIrradianceIsAddedToTheColours) {
  const Scene scene = protocol::loadSceneFile(kCornell);
  Engine engine(scene);
  const Mesh mesh = engine.mesh();
  Mesh indirect = mesh;
  for (ReceiverMesh& r : indirect.receivers)
    for (Vec3& e : r.irradiance) e = Vec3(1.0, 2.0, 3.0);
  GlbOptions options;
  options.colorScale = 0.25;
  options.indirect = &indirect;
  const tinygltf::Model model = readGlb(meshToGlb(engine.scene(), mesh, options).bytes);
  EXPECT_TRUE(model.asset.extras.Get("penumbra").Get("indirect").Get<bool>());
  const ReceiverMesh& first = mesh.receivers[0];
  ASSERT_EQ(first.face.object, scene.handleOf(0));
  const std::vector<float> colors = floats(model, model.meshes[0].primitives[0].attributes.at("COLOR_0"));
  for (int c = 0; c < 3; ++c)
    EXPECT_FLOAT_EQ(colors[size_t(c)],
                    float(scene.albedo(first.face)[c] / M_PI * (first.irradiance[0][c] + double(c + 1)) * 0.25));
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
