// Test helper: the glTF test models the compression and cross-check tests share: a tessellated
// torus, the room around it (a floor and a lamp), its primitive written plainly or quantized
// (KHR_mesh_quantization), and the imported torus's shape to compare. Header-only; test use.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "gltf_model_writer.h"
#include "interchange/scene_import.h"

namespace penumbra::interchange {

// A torus of rings × sides quads as triangles around the y axis, 0.6 m across, at y = 1.
struct TriangleMesh {
  std::vector<Vec3> positions;
  std::vector<uint32_t> indices;
};
inline TriangleMesh torus(int rings, int sides) {
  TriangleMesh m;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const double a = 2 * M_PI * i / rings, b = 2 * M_PI * j / sides;
      m.positions.push_back(Vec3((0.22 + 0.08 * std::cos(b)) * std::cos(a), 1 + 0.08 * std::sin(b),
                                 (0.22 + 0.08 * std::cos(b)) * std::sin(a)));
    }
  auto at = [&](int i, int j) { return uint32_t((i % rings) * sides + (j % sides)); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j)
      m.indices.insert(m.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i, j),
                                         at(i + 1, j + 1), at(i + 1, j)});
  return m;
}

// The room around the model: a floor and a lamp (so no default studio is added).
inline ModelWriter roomWriter() {
  ModelWriter w;
  const int grey = w.material("grey", {0.5, 0.6, 0.7}, {0, 0, 0}, 1);
  const int lamp = w.material("lamp", {1, 1, 1}, {1, 1, 1}, 8);
  w.quad("floor", {{{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}}}, grey, {0, 0, 0});
  w.quad("lamp", {{{-0.5, 0, -0.5}, {0.5, 0, -0.5}, {0.5, 0, 0.5}, {-0.5, 0, 0.5}}}, lamp,
         {0, 3, 0});
  return w;
}

inline tinygltf::Primitive plainPrimitive(ModelWriter& w, const TriangleMesh& m) {
  std::vector<float> xyz;
  for (const Vec3& p : m.positions) xyz.insert(xyz.end(), {float(p.x), float(p.y), float(p.z)});
  tinygltf::Primitive p;
  p.mode = TINYGLTF_MODE_TRIANGLES;
  p.attributes["POSITION"] = w.accessor(xyz.data(), xyz.size() * 4, m.positions.size(),
                                        TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
  p.indices = w.accessor(m.indices.data(), m.indices.size() * 4, m.indices.size(),
                         TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR);
  return p;
}

// Positions as integers of `componentType` (normalized or not) with the scale that undoes
// the quantization returned for the node: KHR_mesh_quantization as gltfpack writes it.
inline tinygltf::Primitive quantizedPrimitive(ModelWriter& w, const TriangleMesh& m,
                                              int componentType, bool normalized, Vec3& nodeScale) {
  const double range = componentType == TINYGLTF_COMPONENT_TYPE_BYTE    ? 127
                       : componentType == TINYGLTF_COMPONENT_TYPE_SHORT ? 32767
                                                                        : 65535;
  // Every coordinate lies in [−1.2, 1.2]; unsigned, shifted by +0.4 into [0, 1.6].
  const bool isSigned = componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  const double extent = isSigned ? 1.2 : 1.6;
  const double step = extent / range;  // metres per integer step
  nodeScale = Vec3(normalized ? extent : step);
  std::vector<uint8_t> bytes;
  for (const Vec3& p : m.positions)
    for (int c = 0; c < 3; ++c) {
      const double v = std::round((isSigned ? p[c] : p[c] + 0.4) / step);
      if (componentType == TINYGLTF_COMPONENT_TYPE_BYTE) {
        bytes.push_back(uint8_t(int8_t(v)));
      } else {
        const uint16_t s = isSigned ? uint16_t(int16_t(v)) : uint16_t(v);
        bytes.push_back(uint8_t(s & 0xff));
        bytes.push_back(uint8_t(s >> 8));
      }
    }
  const size_t size = componentType == TINYGLTF_COMPONENT_TYPE_BYTE ? 1 : 2;
  std::vector<uint8_t> padded;
  for (size_t i = 0; i < m.positions.size();
       ++i) {  // vertex attributes are 4-byte aligned: stride 4 or 8
    padded.insert(padded.end(), bytes.begin() + long(3 * size * i),
                  bytes.begin() + long(3 * size * (i + 1)));
    while (padded.size() % 4) padded.push_back(0);
  }
  tinygltf::Primitive p;
  p.mode = TINYGLTF_MODE_TRIANGLES;
  p.attributes["POSITION"] = w.accessor(padded.data(), padded.size(), m.positions.size(),
                                        componentType, TINYGLTF_TYPE_VEC3, normalized);
  w.model().bufferViews.back().byteStride = size == 1 ? 4 : 8;
  p.indices = w.accessor(m.indices.data(), m.indices.size() * 4, m.indices.size(),
                         TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR);
  if (!isSigned) w.model().accessors[size_t(p.attributes["POSITION"])].minValues = {0, 0, 0};
  return p;
}

// The model object's faces, total area and bounds.
struct Shape {
  size_t faces = 0;
  double area = 0;
  Vec3 low{INFINITY}, high{-INFINITY};
};
inline Shape shapeOf(const ImportResult& result) {
  Shape s;
  const auto index = result.scene.findObject("torus");
  EXPECT_TRUE(index);
  if (!index) return s;
  for (const Face& face : result.scene.faces()) {
    if (face.id.object != result.scene.handleOf(*index)) continue;
    ++s.faces;
    s.area += face.area;
    for (const Vec3& p : face.polygon) s.low = glm::min(s.low, p), s.high = glm::max(s.high, p);
  }
  return s;
}

// Same surface within the quantization step: coplanar triangle pairs the plain file joins into
// one face may stay two once quantized, so the face count may only grow, up to the triangles.
inline void expectSameShape(const Shape& a, const Shape& b, double tolerance, size_t triangles,
                            const std::string& label) {
  EXPECT_GE(b.faces, a.faces) << label;
  EXPECT_LE(b.faces, triangles) << label;
  EXPECT_NEAR(a.area, b.area, 20 * tolerance * a.area) << label;
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(a.low[c], b.low[c], tolerance) << label;
    EXPECT_NEAR(a.high[c], b.high[c], tolerance) << label;
  }
}

}  // namespace penumbra::interchange
