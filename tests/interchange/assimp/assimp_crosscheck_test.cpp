// A second reader as a cross-check (issue 40): Debian's assimp (libassimp) reads the OBJ and GLB
// files the interchange tests import and the GLBs the exporter writes, and agrees with ours on
// the triangle count and the axis-aligned bounds. Ours: the exporter's counts and the scene's
// polygons for an export, the import report's triangles_read and bounds for an import. Bounds
// agree within float precision: assimp holds coordinates as float32 (ai_real), as a GLB does,
// so each may be off by 4 float ulps of the largest coordinate (rounding, and assimp's node
// transforms applied in float).
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../gltf_test_models.h"
#include "../interchange_fixtures.h"
#include "core/engine/engine.h"
#include "interchange/glb_export.h"
#include "interchange/scene_import.h"
#include "protocol/scene_json.h"
#include "scenegen/model_scene.h"

namespace penumbra::interchange {
namespace {

using testing::scratchDir;

// A file's triangles and the bounds of their corners.
struct Shape {
  size_t triangles = 0;
  Vec3 low{INFINITY}, high{-INFINITY};
  void add(const Vec3& p) { low = glm::min(low, p), high = glm::max(high, p); }
};

// Assimp's reading, in world space (node transforms applied); only corners of triangles count
// (a GLB's LINES primitive, our --edges, is not a surface).
Shape assimpShape(const std::string& path) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate);
  Shape shape;
  if (!scene || !scene->mRootNode) {
    ADD_FAILURE() << "assimp cannot read " << path << ": " << importer.GetErrorString();
    return shape;
  }
  std::vector<std::pair<const aiNode*, aiMatrix4x4>> stack{
      {scene->mRootNode, scene->mRootNode->mTransformation}};
  while (!stack.empty()) {
    const auto [node, worldFromNode] = stack.back();
    stack.pop_back();
    for (unsigned m = 0; m < node->mNumMeshes; ++m) {
      const aiMesh* mesh = scene->mMeshes[node->mMeshes[m]];
      for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices != 3) continue;
        ++shape.triangles;
        for (unsigned k = 0; k < 3; ++k) {
          const aiVector3D p = worldFromNode * mesh->mVertices[face.mIndices[k]];
          shape.add(Vec3(p.x, p.y, p.z));
        }
      }
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c)
      stack.push_back({node->mChildren[c], worldFromNode * node->mChildren[c]->mTransformation});
  }
  return shape;
}

// Where assimp and we disagree, one line each; empty when the counts are equal and every bound
// is within 4 float ulps of the largest coordinate.
std::vector<std::string> disagreements(const Shape& ours, const Shape& theirs) {
  std::vector<std::string> out;
  if (ours.triangles != theirs.triangles)
    out.push_back("triangles: ours " + std::to_string(ours.triangles) + ", assimp " +
                  std::to_string(theirs.triangles));
  double largest = 0;
  for (int c = 0; c < 3; ++c)
    largest = std::max({largest, std::abs(ours.low[c]), std::abs(ours.high[c])});
  const double tolerance = 4 * std::ldexp(largest, -23);
  for (int c = 0; c < 3; ++c)
    for (const auto& [name, a, b] : {std::tuple{"min", ours.low[c], theirs.low[c]},
                                     std::tuple{"max", ours.high[c], theirs.high[c]}})
      if (!(std::abs(a - b) <= tolerance)) {
        std::ostringstream line;
        line.precision(9);
        line << name << "[" << c << "]: ours " << a << ", assimp " << b << " (tolerance "
             << tolerance << ")";
        out.push_back(line.str());
      }
  return out;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += "  " + line + "\n";
  return text;
}

// The scene's polygons (faces and lights) as the exporter fans them.
Shape sceneShape(const Scene& scene) {
  Shape shape;
  for (const Face& face : scene.faces()) {
    shape.triangles += face.polygon.size() - 2;
    for (const Vec3& p : face.polygon) shape.add(p);
  }
  for (const Light& light : scene.lights()) {
    shape.triangles += light.polygon.size() - 2;
    for (const Vec3& p : light.polygon) shape.add(p);
  }
  return shape;
}

// What our importer read, from its report.
Shape importedShape(const ImportReport& report) {
  Shape shape;
  shape.triangles = report.trianglesRead;
  shape.low = report.boundsMin;
  shape.high = report.boundsMax;
  return shape;
}

void writeBytes(const std::filesystem::path& path, const std::vector<uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// Exports `scene` as `penumbra build --out X.glb` does (plain, and with the discontinuity lines),
// and checks assimp reads the exporter's triangles within the scene's bounds; then imports the
// GLB and checks assimp agrees with the import report too.
void crossCheckExport(const Scene& scene, const std::filesystem::path& dir,
                      const std::string& name) {
  Engine engine(scene);
  const Mesh mesh = engine.mesh();
  Shape expected = sceneShape(engine.scene());
  for (const bool edges : {false, true}) {
    GlbOptions options;
    if (edges) options.edges = {Segment3{expected.low, expected.high}};
    const std::filesystem::path path = dir / (name + (edges ? "-edges.glb" : ".glb"));
    const GlbFile glb = saveMeshGlb(engine.scene(), mesh, path.string(), options);
    // The exporter's object triangles (the lit mesh) plus each light's fan.
    expected.triangles = glb.triangles;
    for (const Light& light : engine.scene().lights())
      expected.triangles += light.polygon.size() - 2;
    EXPECT_EQ(joined(disagreements(expected, assimpShape(path.string()))), "") << path;
    if (edges) continue;
    ImportOptions plain;
    plain.studio = false;
    const ImportResult imported = importSceneFile(path.string(), plain);
    EXPECT_EQ(joined(disagreements(importedShape(imported.report), assimpShape(path.string()))), "")
        << path << " imported";
  }
}

TEST(AssimpCrossCheck, TheCheckCanFail) {
  Shape ours;
  ours.triangles = 2;
  ours.add(Vec3(0, 0, 0));
  ours.add(Vec3(1, 2, 3));
  EXPECT_TRUE(disagreements(ours, ours).empty());
  Shape miscounted = ours;
  ++miscounted.triangles;
  EXPECT_EQ(disagreements(ours, miscounted).size(), 1u);
  Shape moved = ours;
  moved.high.y = std::nextafter(float(2), 3.0f) + 8 * std::ldexp(3.0, -23);  // past 4 ulps of 3
  EXPECT_EQ(disagreements(ours, moved).size(), 1u);

  // A GLB whose index accessor lost its last triangle: assimp reads one fewer than the model has.
  const std::filesystem::path dir = scratchDir();
  ModelWriter w = roomWriter();
  w.node("torus", plainPrimitive(w, torus(8, 6)));
  w.model().accessors[size_t(w.model().meshes.back().primitives[0].indices)].count -= 3;
  writeBytes(dir / "short.glb", w.write(true));
  Shape full;
  full.triangles = 2 + 2 + 8 * 6 * 2;  // floor, lamp, torus
  const Shape read = assimpShape((dir / "short.glb").string());
  EXPECT_EQ(read.triangles, full.triangles - 1);
  full.low = read.low, full.high = read.high;
  EXPECT_EQ(disagreements(full, read).size(), 1u);
}

TEST(AssimpCrossCheck, ObjFixtures) {
  for (const auto& entry : std::filesystem::directory_iterator(testing::kData)) {
    if (entry.path().extension() != ".obj") continue;
    const ImportResult imported = importSceneFile(entry.path().string(), {});
    EXPECT_EQ(
        joined(disagreements(importedShape(imported.report), assimpShape(entry.path().string()))),
        "")
        << entry.path().filename();
  }
}

// The torus the compression test imports, plainly, quantized (KHR_mesh_quantization) and under
// a rotated, scaled and moved parent node. Debian's assimp 5.2.5 reads a quantized file's
// triangles but not its positions (it takes the normalized shorts for floats: coordinates of
// 1e31), so there only the counts are compared. Draco is not compared: Debian's assimp 5.2.5 is
// built without it.
TEST(AssimpCrossCheck, GltfModels) {
  const std::filesystem::path dir = scratchDir();
  const TriangleMesh mesh = torus(24, 12);
  ModelWriter plain = roomWriter();
  plain.node("torus", plainPrimitive(plain, mesh));
  writeBytes(dir / "plain.glb", plain.write(true));
  ModelWriter quantized = roomWriter();
  Vec3 scale(1.0);
  const tinygltf::Primitive primitive =
      quantizedPrimitive(quantized, mesh, TINYGLTF_COMPONENT_TYPE_SHORT, true, scale);
  quantized.node("torus", primitive, scale);
  quantized.model().extensionsRequired =
      quantized.model().extensionsUsed = {"KHR_mesh_quantization"};
  writeBytes(dir / "quantized.glb", quantized.write(true));
  // The torus under a parent: both readers compose the node transforms.
  ModelWriter nested = roomWriter();
  nested.node("torus", plainPrimitive(nested, mesh));
  tinygltf::Model& model = nested.model();
  model.nodes.back().rotation = {0, 0, std::sin(0.3), std::cos(0.3)};
  tinygltf::Node parent;
  parent.translation = {0.5, 0.25, -1};
  parent.rotation = {std::sin(0.4), 0, 0, std::cos(0.4)};
  parent.scale = {2, 1, 3};
  parent.children = {int(model.nodes.size() - 1)};
  model.nodes.push_back(parent);
  model.scenes[0].nodes.back() = int(model.nodes.size() - 1);
  writeBytes(dir / "nested.glb", nested.write(true));
  for (const char* name : {"plain.glb", "quantized.glb", "nested.glb"}) {
    const std::string path = (dir / name).string();
    const ImportResult imported = importSceneFile(path, {});
    EXPECT_EQ(imported.report.trianglesRead, 2 + 2 + mesh.indices.size() / 3) << name;
    const Shape theirs = assimpShape(path);
    if (std::string(name) == "quantized.glb") {
      EXPECT_EQ(imported.report.trianglesRead, theirs.triangles);
      EXPECT_GT(theirs.high.x, 1e6)
          << "assimp reads quantized positions now: compare its bounds too";
      continue;
    }
    EXPECT_EQ(joined(disagreements(importedShape(imported.report), theirs)), "") << name;
  }
}

// Every bundled scene's GLB, as `penumbra build SCENE --out X.glb` writes it (the --indirect
// export differs only in its colours and _RADIANCE, not in its geometry).
TEST(AssimpCrossCheck, BundledSceneExports) {
  const std::filesystem::path dir = scratchDir();
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(PENUMBRA_SOURCE_DIR) + "/scenes")) {
    const std::string file = entry.path().filename().string();
    if (!file.ends_with(".scene.json")) continue;
    SCOPED_TRACE(file);
    crossCheckExport(protocol::loadSceneFile(entry.path().string()), dir,
                     file.substr(0, file.find('.')));
  }
}

TEST(AssimpCrossCheck, GeneratedModelExports) {
  const std::filesystem::path dir = scratchDir();
  for (const ModelKind kind : {ModelKind::Teapot, ModelKind::TorusKnot, ModelKind::Scan}) {
    ModelSceneOptions options;
    options.kind = kind;
    options.triangles = minModelTriangles(kind);
    options.rest = true;
    SCOPED_TRACE(modelKindName(kind));
    crossCheckExport(makeModelScene(options), dir, modelKindName(kind));
  }
}

}  // namespace
}  // namespace penumbra::interchange
