// EXT_meshopt_compression (issue 40): the compression test's torus and room written plainly, then
// with buffer views compressed by Debian's libmeshoptimizer encoders (vertex streams, triangle
// lists, index sequences; the exponential filter on positions), import to the same geometry:
// required with the fallback buffer empty (GLB and glTF text), or only used with the plain data
// in the fallback. The octahedral and quaternion filters decode to the vectors encoded; a broken
// stream or extension object is an error at its key path.
#include "interchange/gltf_meshopt.h"

#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gltf_test_models.h"
#include "interchange/gltf_json_edit.h"
#include "interchange/scene_import.h"
#include "protocol/validation_error.h"

namespace penumbra::interchange {
namespace {

// One plain buffer view to compress, as an encoder would: mode, filter and its mantissa bits.
struct Compression {
  int view;
  std::string mode;
  std::string filter = "NONE";
  int bits = 0;
};

// The view's element stride: its own, or the size of an accessor's element over it.
size_t strideOf(const tinygltf::Model& model, int view) {
  if (model.bufferViews[size_t(view)].byteStride) return model.bufferViews[size_t(view)].byteStride;
  for (const tinygltf::Accessor& a : model.accessors)
    if (a.bufferView == view)
      return size_t(tinygltf::GetNumComponentsInType(uint32_t(a.type)) *
                    tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType)));
  ADD_FAILURE() << "no accessor over view " << view;
  return 4;
}

// The data of `count` elements of `stride` bytes as `mode` encodes it, after the filter.
std::vector<unsigned char> encode(const Compression& c, const unsigned char* plain, size_t count,
                                  size_t stride) {
  std::vector<unsigned char> data(plain, plain + count * stride);
  if (c.filter == "EXPONENTIAL")
    meshopt_encodeFilterExp(data.data(), count, stride, c.bits,
                            reinterpret_cast<const float*>(plain));
  std::vector<unsigned char> out;
  size_t size = 0;
  if (c.mode == "ATTRIBUTES") {
    out.resize(meshopt_encodeVertexBufferBound(count, stride));
    size = meshopt_encodeVertexBuffer(out.data(), out.size(), data.data(), count, stride);
  } else {
    std::vector<unsigned int> indices(count);
    for (size_t i = 0; i < count; ++i) {
      uint16_t narrow = 0;
      if (stride == 2)
        std::memcpy(&narrow, data.data() + 2 * i, 2), indices[i] = narrow;
      else
        std::memcpy(&indices[i], data.data() + 4 * i, 4);
    }
    const size_t vertices = *std::max_element(indices.begin(), indices.end()) + 1;
    if (c.mode == "TRIANGLES") {
      out.resize(meshopt_encodeIndexBufferBound(count, vertices));
      size = meshopt_encodeIndexBuffer(out.data(), out.size(), indices.data(), count);
    } else {
      out.resize(meshopt_encodeIndexSequenceBound(count, vertices));
      size = meshopt_encodeIndexSequence(out.data(), out.size(), indices.data(), count);
    }
  }
  EXPECT_GT(size, 0u) << c.mode;
  out.resize(size);
  return out;
}

// How the fallback buffer (buffer 1, where the compressed views point) is written.
enum class Fallback { Empty, Plain };

// The model with the views compressed into buffer 0 and their plain bytes moved to the fallback
// buffer (and zeroed where they were), written as GLB or glTF text; the extension is required
// with an empty fallback, only used with the plain one. tinygltf writes neither buffer nor
// view extensions, so they are added to the written JSON.
std::vector<uint8_t> meshoptFile(ModelWriter& w, const std::vector<Compression>& views,
                                 Fallback fallback, bool binary) {
  tinygltf::Model& model = w.model();
  model.buffers.emplace_back();
  nlohmann::json extensions = nlohmann::json::object();
  for (const Compression& c : views) {
    tinygltf::BufferView& view = model.bufferViews[size_t(c.view)];
    const size_t stride = strideOf(model, c.view), count = view.byteLength / stride;
    std::vector<unsigned char>& plain = model.buffers[0].data;
    const std::vector<unsigned char> compressed =
        encode(c, plain.data() + view.byteOffset, count, stride);
    const size_t at = w.append(compressed.data(), compressed.size());
    const size_t moved = w.append(plain.data() + view.byteOffset, view.byteLength, 1);
    std::memset(plain.data() + view.byteOffset, 0, view.byteLength);
    view.buffer = 1;
    view.byteOffset = moved;
    if (c.mode == "ATTRIBUTES") view.byteStride = stride;
    nlohmann::json e = {
        {"buffer", 0},          {"byteOffset", at}, {"byteLength", compressed.size()},
        {"byteStride", stride}, {"count", count},   {"mode", c.mode}};
    if (c.filter != "NONE") e["filter"] = c.filter;
    extensions[std::to_string(c.view)] = e;
  }
  model.extensionsUsed.push_back("EXT_meshopt_compression");
  if (fallback == Fallback::Empty) model.extensionsRequired.push_back("EXT_meshopt_compression");
  return editGltfJson(w.write(binary), [&](nlohmann::json& gltf) {
    for (const auto& [view, e] : extensions.items())
      gltf["bufferViews"][std::stoul(view)]["extensions"]["EXT_meshopt_compression"] = e;
    nlohmann::json& buffer = gltf["buffers"][1];
    buffer["extensions"]["EXT_meshopt_compression"] = {{"fallback", true}};
    if (fallback == Fallback::Empty) buffer.erase("uri");
    return true;
  });
}

int viewOf(ModelWriter& w, int accessor) {
  return w.model().accessors[size_t(accessor)].bufferView;
}

// The room (floor and lamp quads, 16-bit indices) and the plain torus, with the views of both
// quads' and the torus's positions and indices compressed losslessly.
std::vector<uint8_t> losslessFile(const TriangleMesh& mesh, Fallback fallback, bool binary) {
  ModelWriter w = roomWriter();
  const tinygltf::Primitive torus = plainPrimitive(w, mesh);
  w.node("torus", torus);
  std::vector<Compression> views;
  for (const tinygltf::Mesh& m : w.model().meshes) {
    views.push_back({viewOf(w, m.primitives[0].attributes.at("POSITION")), "ATTRIBUTES"});
    views.push_back({viewOf(w, m.primitives[0].indices), "TRIANGLES"});
  }
  return meshoptFile(w, views, fallback, binary);
}

void expectSameScene(const ImportResult& a, const ImportResult& b, const std::string& label) {
  EXPECT_EQ(a.scene.faces().size(), b.scene.faces().size()) << label;
  EXPECT_EQ(a.scene.lights().size(), b.scene.lights().size()) << label;
  const Shape s = shapeOf(a), t = shapeOf(b);
  EXPECT_EQ(s.faces, t.faces) << label;
  EXPECT_DOUBLE_EQ(s.area, t.area) << label;
  EXPECT_EQ(s.low, t.low) << label;
  EXPECT_EQ(s.high, t.high) << label;
}

TEST(GltfMeshopt, CompressedViewsImportAsThePlainFile) {
  const TriangleMesh mesh = torus(24, 12);
  ModelWriter w = roomWriter();
  w.node("torus", plainPrimitive(w, mesh));
  const ImportResult plain = importSceneBytes(w.write(true), "plain.glb", {}, {});
  ASSERT_EQ(plain.scene.lights().size(), 1u);

  struct Case {
    const char* label;
    Fallback fallback;
    bool binary;
  };
  for (const Case& c : {Case{"required, no fallback data, GLB", Fallback::Empty, true},
                        Case{"required, no fallback data, glTF", Fallback::Empty, false},
                        Case{"used with the plain fallback, GLB", Fallback::Plain, true}}) {
    const ImportResult meshopt =
        importSceneBytes(losslessFile(mesh, c.fallback, c.binary),
                         c.binary ? "meshopt.glb" : "meshopt.gltf", {}, {});
    EXPECT_EQ(meshopt.report.repaired("meshopt_compressed_buffer_views"), 6u)
        << c.label << ": " << meshopt.report.summary();
    expectSameScene(plain, meshopt, c.label);
  }
}

TEST(GltfMeshopt, QuantizedAndFilteredPositionsImportAsThePlainFile) {
  const TriangleMesh mesh = torus(24, 12);
  ModelWriter plainWriter = roomWriter();
  plainWriter.node("torus", plainPrimitive(plainWriter, mesh));
  const Shape reference = shapeOf(importSceneBytes(plainWriter.write(true), "plain.glb", {}, {}));
  const size_t triangles = mesh.indices.size() / 3;

  // gltfpack's default: normalized shorts (stride 8) under the node scale that undoes them, the
  // indices as a sequence.
  ModelWriter w = roomWriter();
  Vec3 scale(1.0);
  const tinygltf::Primitive quantized =
      quantizedPrimitive(w, mesh, TINYGLTF_COMPONENT_TYPE_SHORT, true, scale);
  w.node("torus", quantized, scale);
  w.model().extensionsUsed = w.model().extensionsRequired = {"KHR_mesh_quantization"};
  const std::vector<uint8_t> file =
      meshoptFile(w,
                  {{viewOf(w, quantized.attributes.at("POSITION")), "ATTRIBUTES"},
                   {viewOf(w, quantized.indices), "INDICES"}},
                  Fallback::Empty, true);
  expectSameShape(reference, shapeOf(importSceneBytes(file, "quantized.glb", {}, {})), 1.2 / 32767,
                  triangles, "quantized");

  // Float positions through the exponential filter: 15-bit mantissas under each vector's exponent.
  ModelWriter f = roomWriter();
  const tinygltf::Primitive floats = plainPrimitive(f, mesh);
  f.node("torus", floats);
  const std::vector<uint8_t> filtered = meshoptFile(
      f, {{viewOf(f, floats.attributes.at("POSITION")), "ATTRIBUTES", "EXPONENTIAL", 15}},
      Fallback::Empty, true);
  expectSameShape(reference, shapeOf(importSceneBytes(filtered, "filtered.glb", {}, {})),
                  1.2 / 16384, triangles, "exponential filter");
}

// A model of one compressed view (buffer 0: the stream; buffer 1: an empty fallback).
tinygltf::Model modelOfOneView(const std::vector<unsigned char>& stream,
                               const tinygltf::Value::Object& extension, size_t byteLength) {
  tinygltf::Model model;
  model.buffers.resize(2);
  model.buffers[0].data = stream;
  tinygltf::BufferView view;
  view.buffer = 1;
  view.byteLength = byteLength;
  view.extensions["EXT_meshopt_compression"] = tinygltf::Value(extension);
  model.bufferViews.push_back(view);
  return model;
}

tinygltf::Value::Object extensionOf(size_t length, size_t stride, size_t count,
                                    const std::string& mode, const std::string& filter) {
  return {{"buffer", tinygltf::Value(0)},
          {"byteLength", tinygltf::Value(int(length))},
          {"byteStride", tinygltf::Value(int(stride))},
          {"count", tinygltf::Value(int(count))},
          {"mode", tinygltf::Value(mode)},
          {"filter", tinygltf::Value(filter)}};
}

tinygltf::Value::Object withMember(tinygltf::Value::Object extension, const std::string& key,
                                   double value) {
  extension[key] = tinygltf::Value(value);
  return extension;
}

// Seeded unit vectors (normals) and unit quaternions.
std::vector<float> unitVectors(size_t count, int components, uint32_t seed) {
  std::vector<float> out;
  for (size_t i = 0; i < count; ++i) {
    std::vector<float> v(static_cast<size_t>(components));
    double norm = 0;
    for (float& x : v) {
      seed = seed * 1664525u + 1013904223u;
      x = float(double(seed >> 8) / double(1u << 24) * 2 - 1);
      norm += double(x) * x;
    }
    for (float& x : v) x = float(x / std::sqrt(norm));
    out.insert(out.end(), v.begin(), v.end());
  }
  return out;
}

TEST(GltfMeshopt, OctahedralAndQuaternionFiltersDecodeToTheEncodedVectors) {
  const size_t count = 200;
  // Normals: 16-bit octahedral in 4 shorts (stride 8), read back as normalized shorts.
  // Rotations: 12-bit quaternions in 4 shorts, equal up to sign.
  struct Case {
    const char* filter;
    int components, bits;
  };
  for (const Case& c : {Case{"OCTAHEDRAL", 3, 16}, Case{"QUATERNION", 4, 12}}) {
    const std::vector<float> vectors = unitVectors(count, c.components, 40);
    std::vector<int16_t> filtered(count * 4);
    if (c.components == 3) {
      std::vector<float> padded;  // the encoder reads 4 floats a vector
      for (size_t i = 0; i < count; ++i)
        padded.insert(padded.end(), {vectors[3 * i], vectors[3 * i + 1], vectors[3 * i + 2], 0});
      meshopt_encodeFilterOct(filtered.data(), count, 8, c.bits, padded.data());
    } else {
      meshopt_encodeFilterQuat(filtered.data(), count, 8, c.bits, vectors.data());
    }
    std::vector<unsigned char> stream(meshopt_encodeVertexBufferBound(count, 8));
    stream.resize(
        meshopt_encodeVertexBuffer(stream.data(), stream.size(), filtered.data(), count, 8));
    tinygltf::Model model = modelOfOneView(
        stream, extensionOf(stream.size(), 8, count, "ATTRIBUTES", c.filter), count * 8);
    ASSERT_EQ(decodeMeshoptViews(model), 1u);
    const tinygltf::BufferView& view = model.bufferViews[0];
    ASSERT_EQ(view.byteLength, count * 8);
    const auto* decoded =
        reinterpret_cast<const int16_t*>(model.buffers[size_t(view.buffer)].data.data());
    const double step = 2.0 / ((1 << (c.bits - 1)) - 1);
    for (size_t i = 0; i < count; ++i) {
      double dot = 0;
      for (int k = 0; k < c.components; ++k)
        dot += decoded[4 * i + size_t(k)] / 32767.0 * vectors[size_t(c.components) * i + size_t(k)];
      EXPECT_NEAR(std::abs(dot), 1, 4 * step) << c.filter << " vector " << i;
    }
  }
}

TEST(GltfMeshopt, ABrokenStreamOrExtensionIsAnErrorAtItsPath) {
  const std::vector<uint32_t> indices = {0, 1, 2, 2, 1, 3};
  std::vector<unsigned char> stream(meshopt_encodeIndexBufferBound(6, 4));
  stream.resize(meshopt_encodeIndexBuffer(stream.data(), stream.size(), indices.data(), 6));
  tinygltf::Model good =
      modelOfOneView(stream, extensionOf(stream.size(), 4, 6, "TRIANGLES", "NONE"), 24);
  ASSERT_EQ(decodeMeshoptViews(good), 1u);
  EXPECT_EQ(0, std::memcmp(good.buffers[2].data.data(), indices.data(), 24));

  std::vector<unsigned char> corrupt = stream;
  corrupt[0] ^= 0xff;  // the header byte names the codec and its version
  struct Case {
    const char* label;
    std::vector<unsigned char> stream;
    tinygltf::Value::Object extension;
    std::string path;
  };
  const std::string at = "bufferViews[0].extensions.EXT_meshopt_compression";
  const Case cases[] = {
      {"corrupt", corrupt, extensionOf(stream.size(), 4, 6, "TRIANGLES", "NONE"), at},
      {"truncated", stream, extensionOf(stream.size() - 4, 4, 6, "TRIANGLES", "NONE"), at},
      {"past the buffer", stream, extensionOf(stream.size() + 1, 4, 6, "TRIANGLES", "NONE"),
       at + ".byteLength"},
      {"mode", stream, extensionOf(stream.size(), 4, 6, "POINTS", "NONE"), at + ".mode"},
      {"not triangles", stream, extensionOf(stream.size(), 4, 5, "TRIANGLES", "NONE"),
       at + ".count"},
      {"index stride", stream, extensionOf(stream.size(), 3, 6, "TRIANGLES", "NONE"),
       at + ".byteStride"},
      {"vertex stride", stream, extensionOf(stream.size(), 6, 6, "ATTRIBUTES", "NONE"),
       at + ".byteStride"},
      {"filter", stream, extensionOf(stream.size(), 4, 6, "ATTRIBUTES", "QUATERNION"),
       at + ".filter"},
      {"huge", stream, extensionOf(stream.size(), 256, 1 << 21, "ATTRIBUTES", "NONE"),
       at + ".count"},
      {"count 1e30", stream,
       withMember(extensionOf(stream.size(), 4, 6, "TRIANGLES", "NONE"), "count", 1e30),
       at + ".count"},
      {"count 6.5", stream,
       withMember(extensionOf(stream.size(), 4, 6, "TRIANGLES", "NONE"), "count", 6.5),
       at + ".count"},
  };
  for (const Case& c : cases) {
    tinygltf::Model model = modelOfOneView(c.stream, c.extension, 24);
    try {
      decodeMeshoptViews(model);
      ADD_FAILURE() << c.label << ": decoded";
    } catch (const protocol::ValidationError& e) {
      EXPECT_EQ(e.path(), c.path) << c.label << ": " << e.what();
    }
  }
}

}  // namespace
}  // namespace penumbra::interchange
