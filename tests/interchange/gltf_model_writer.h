// Test helper: builds a glTF model with tinygltf (materials, quads and triangle meshes each
// under a node of their own) and writes it as GLB or glTF. Header-only; test use.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "core/geom/vec.h"

namespace penumbra::interchange {

// Builds a model: materials, and meshes of one primitive each under a node of their own.
class ModelWriter {
 public:
  ModelWriter() {
    model_.asset.version = "2.0";
    model_.buffers.emplace_back();
    model_.scenes.emplace_back();
    model_.defaultScene = 0;
  }
  int material(const std::string& name, const Vec3& base, const Vec3& emissive, double strength) {
    tinygltf::Material m;
    m.name = name;
    m.pbrMetallicRoughness.baseColorFactor = {base.x, base.y, base.z, 1};
    m.emissiveFactor = {emissive.x, emissive.y, emissive.z};
    if (strength != 1)
      m.extensions["KHR_materials_emissive_strength"] =
          tinygltf::Value(tinygltf::Value::Object{{"emissiveStrength", tinygltf::Value(strength)}});
    model_.materials.push_back(m);
    return int(model_.materials.size() - 1);
  }
  // Two indexed triangles; corners counter-clockwise seen from the front; translation on the node.
  void quad(const std::string& name, const std::array<Vec3, 4>& corners, int material, const Vec3& translation) {
    std::vector<float> positions;
    for (const Vec3& c : corners) positions.insert(positions.end(), {float(c.x), float(c.y), float(c.z)});
    const std::vector<uint16_t> indices = {0, 1, 2, 0, 2, 3};
    tinygltf::Primitive p;
    p.mode = TINYGLTF_MODE_TRIANGLES;
    p.material = material;
    p.attributes["POSITION"] =
        accessor(positions.data(), positions.size() * 4, 4, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
    p.indices = accessor(indices.data(), indices.size() * 2, 6, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR);
    node(name, p, Vec3(1.0), translation);
  }
  // A node showing a mesh of one primitive, with its scale and translation.
  void node(const std::string& name, const tinygltf::Primitive& primitive, const Vec3& scale = Vec3(1.0),
            const Vec3& translation = Vec3(0.0)) {
    tinygltf::Mesh mesh;
    mesh.primitives.push_back(primitive);
    model_.meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = name;
    node.mesh = int(model_.meshes.size() - 1);
    if (scale != Vec3(1.0)) node.scale = {scale.x, scale.y, scale.z};
    node.translation = {translation.x, translation.y, translation.z};
    model_.nodes.push_back(node);
    model_.scenes[0].nodes.push_back(int(model_.nodes.size() - 1));
  }
  // `bytes` appended to a buffer (4-byte aligned); their offset in it.
  size_t append(const void* data, size_t bytes, size_t buffer = 0) {
    std::vector<unsigned char>& to = model_.buffers[buffer].data;
    while (to.size() % 4) to.push_back(0);
    const size_t offset = to.size();
    to.resize(offset + bytes);
    std::memcpy(to.data() + offset, data, bytes);
    return offset;
  }
  // A buffer view over `bytes` appended to the buffer; its index.
  int view(const void* data, size_t bytes) {
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = append(data, bytes);
    view.byteLength = bytes;
    model_.bufferViews.push_back(view);
    return int(model_.bufferViews.size() - 1);
  }
  // An accessor over data in a buffer view of its own, or with no buffer view when data is
  // null (a Draco primitive's accessors give only count and type).
  int accessor(const void* data, size_t bytes, size_t count, int componentType, int type, bool normalized = false) {
    tinygltf::Accessor a;
    a.bufferView = data ? view(data, bytes) : -1;
    a.normalized = normalized;
    a.componentType = componentType;
    a.type = type;
    a.count = count;
    if (type == TINYGLTF_TYPE_VEC3) {
      a.minValues = {-100, -100, -100};
      a.maxValues = {100, 100, 100};
    }
    model_.accessors.push_back(a);
    return int(model_.accessors.size() - 1);
  }
  tinygltf::Model& model() { return model_; }
  std::vector<uint8_t> write(bool binary) {
    tinygltf::TinyGLTF writer;
    std::ostringstream out;
    EXPECT_TRUE(writer.WriteGltfSceneToStream(&model_, out, false, binary));
    const std::string s = out.str();
    return std::vector<uint8_t>(s.begin(), s.end());
  }

 private:
  tinygltf::Model model_;
};

}  // namespace penumbra::interchange
