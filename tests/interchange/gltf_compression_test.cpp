// Compressed and quantized glTF geometry, as real-world files store it (issue 40): a tessellated
// torus written plainly, Draco-compressed (KHR_draco_mesh_compression, by Debian's libdraco
// encoder) and quantized (KHR_mesh_quantization: normalized shorts, unnormalized unsigned shorts
// and signed bytes, each with the node scale that undoes it) imports to the same geometry; a
// file requiring an extension the importer does not read is refused naming it.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <vector>

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>

#include "gltf_test_models.h"
#include "interchange/scene_import.h"
#include "protocol/validation_error.h"

namespace penumbra::interchange {
namespace {

// The mesh as a Draco stream (16-bit positions, as exporters default to) in a KHR_draco_mesh_compression primitive.
tinygltf::Primitive dracoPrimitive(ModelWriter& w, const TriangleMesh& m) {
  draco::TriangleSoupMeshBuilder builder;
  const size_t faces = m.indices.size() / 3;
  builder.Start(int(faces));
  const int position = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  for (size_t f = 0; f < faces; ++f) {
    float corner[3][3];
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) corner[k][c] = float(m.positions[m.indices[3 * f + size_t(k)]][c]);
    builder.SetAttributeValuesForFace(position, draco::FaceIndex(uint32_t(f)), corner[0], corner[1], corner[2]);
  }
  const std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
  EXPECT_TRUE(mesh);
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 16);
  draco::EncoderBuffer stream;
  EXPECT_TRUE(encoder.EncodeMeshToBuffer(*mesh, &stream).ok());
  tinygltf::Primitive p;
  p.mode = TINYGLTF_MODE_TRIANGLES;
  p.attributes["POSITION"] =
      w.accessor(nullptr, 0, mesh->num_points(), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
  p.indices = w.accessor(nullptr, 0, 3 * mesh->num_faces(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR);
  const int view = w.view(stream.data(), stream.size());
  p.extensions["KHR_draco_mesh_compression"] = tinygltf::Value(tinygltf::Value::Object{
      {"bufferView", tinygltf::Value(view)},
      {"attributes", tinygltf::Value(tinygltf::Value::Object{
                         {"POSITION", tinygltf::Value(int(mesh->attribute(position)->unique_id()))}})}});
  return p;
}

std::vector<uint8_t> fileWith(const std::function<tinygltf::Primitive(ModelWriter&)>& primitive,
                              const std::vector<std::string>& required) {
  ModelWriter w = roomWriter();
  w.node("torus", primitive(w));
  w.model().extensionsUsed = required;
  w.model().extensionsRequired = required;
  return w.write(true);
}

TEST(GltfCompression, DracoAndQuantizedGeometryImportAsThePlainFile) {
  const TriangleMesh mesh = torus(24, 12);
  const ImportResult plain = importSceneBytes(fileWith([&](ModelWriter& w) { return plainPrimitive(w, mesh); }, {}),
                                              "plain.glb", {}, {});
  const Shape reference = shapeOf(plain);
  ASSERT_GE(reference.faces, mesh.indices.size() / 3 * 9 / 10);  // a few coplanar pairs join

  const ImportResult draco = importSceneBytes(
      fileWith([&](ModelWriter& w) { return dracoPrimitive(w, mesh); }, {"KHR_draco_mesh_compression"}), "draco.glb", {}, {});
  EXPECT_EQ(draco.report.repaired("draco_compressed_primitives"), 1u) << draco.report.summary();
  expectSameShape(reference, shapeOf(draco), 1.2 * 2 / 65535, mesh.indices.size() / 3, "draco");

  struct Case {
    const char* label;
    int type;
    bool normalized;
    double step;
  };
  const Case cases[] = {{"normalized short", TINYGLTF_COMPONENT_TYPE_SHORT, true, 1.2 / 32767},
                        {"unsigned short", TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, false, 1.6 / 65535},
                        {"normalized byte", TINYGLTF_COMPONENT_TYPE_BYTE, true, 1.2 / 127}};
  for (const Case& c : cases) {
    // The node's scale (and, unsigned, its shift back) undoes the quantization.
    Vec3 scale(1.0);
    ModelWriter w = roomWriter();
    const tinygltf::Primitive primitive = quantizedPrimitive(w, mesh, c.type, c.normalized, scale);
    w.node("torus", primitive, scale, c.type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? Vec3(-0.4) : Vec3(0.0));
    w.model().extensionsRequired = w.model().extensionsUsed = {"KHR_mesh_quantization"};
    const ImportResult quantized = importSceneBytes(w.write(true), "quantized.glb", {}, {});
    // A byte's step (1 cm) moves corners off their neighbours' planes: faces may join differently.
    if (c.type == TINYGLTF_COMPONENT_TYPE_BYTE) {
      const Shape s = shapeOf(quantized);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.low[k], reference.low[k], c.step) << c.label;
    } else {
      expectSameShape(reference, shapeOf(quantized), c.step, mesh.indices.size() / 3, c.label);
    }
  }
}

TEST(GltfCompression, AnUnreadRequiredExtensionIsRefusedByName) {
  const TriangleMesh mesh = torus(8, 6);
  // Instancing places copies of the mesh by per-instance transforms the importer does not apply.
  const std::vector<uint8_t> file = fileWith([&](ModelWriter& w) { return plainPrimitive(w, mesh); },
                                             {"KHR_mesh_quantization", "EXT_mesh_gpu_instancing"});
  try {
    importSceneBytes(file, "instanced.glb", {}, {});
    FAIL() << "a file requiring EXT_mesh_gpu_instancing was imported";
  } catch (const protocol::ValidationError& e) {
    EXPECT_EQ(e.path(), "extensionsRequired[1]");
    EXPECT_NE(std::string(e.what()).find("EXT_mesh_gpu_instancing"), std::string::npos) << e.what();
  }
  // Used but not required: a reader may ignore it, and the plain data is there.
  ModelWriter w = roomWriter();
  w.node("torus", plainPrimitive(w, mesh));
  w.model().extensionsUsed = {"EXT_mesh_gpu_instancing"};
  EXPECT_NO_THROW(importSceneBytes(w.write(true), "optional.glb", {}, {}));
}

TEST(GltfCompression, ACorruptDracoStreamIsAnErrorWithItsPath) {
  const TriangleMesh mesh = torus(8, 6);
  ModelWriter w = roomWriter();
  tinygltf::Primitive p = dracoPrimitive(w, mesh);
  std::vector<unsigned char>& buffer = w.model().buffers[0].data;
  const tinygltf::BufferView& view = w.model().bufferViews.back();
  for (size_t i = view.byteOffset + 8; i < view.byteOffset + view.byteLength; ++i) buffer[i] = uint8_t(i * 37);
  w.node("torus", p);
  w.model().extensionsRequired = w.model().extensionsUsed = {"KHR_draco_mesh_compression"};
  try {
    importSceneBytes(w.write(true), "corrupt.glb", {}, {});
    FAIL() << "a corrupt Draco stream was imported";
  } catch (const protocol::ValidationError& e) {
    EXPECT_NE(e.path().find("KHR_draco_mesh_compression"), std::string::npos) << e.path() << ": " << e.what();
  }
}

}  // namespace
}  // namespace penumbra::interchange
