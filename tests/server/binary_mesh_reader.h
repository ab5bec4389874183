// The binary mesh read exactly as docs/API.md "Binary" describes it (layout 4), independently of
// server/mesh_binary.cpp, for tests: a part's irradiance expanded to r, g, b per vertex (one
// channel: the value times the tint, in f32, as a page does). Throws std::runtime_error on bytes
// not of that layout.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra::server::test {

struct BinaryMesh {
  uint32_t layout = 0, version = 0, flags = 0, since = 0;
  std::vector<std::string> objects;
  struct Part {  // one display chunk of a receiver
    uint32_t object, face;
    int32_t x, y;
    uint32_t vertices, triangles, version;
    float normal[3];
    uint32_t channels;  // 1: one value per vertex times the tint; 3: r, g, b
    float tint[3];
    std::vector<float> positions, irradiance;  // irradiance: r, g, b per vertex
    std::vector<float> indirect;               // with header flag 2, r, g, b per vertex
    std::vector<uint8_t> classes;
    std::vector<uint32_t> indices;
  };
  std::vector<Part> parts;
  struct ValuePart {  // a part whose irradiance alone changed
    uint32_t object, face;
    int32_t x, y;
    uint32_t vertices, version, channels;  // as Part's
    float tint[3];
    std::vector<float> irradiance;  // r, g, b per vertex
  };
  std::vector<ValuePart> valueParts;
  struct Removed {
    uint32_t object, face;
    int32_t x, y;
  };
  std::vector<Removed> removed;
  uint32_t totalVertices = 0, totalTriangles = 0;
};

// Whether a decoded channel stands for the f32 value `sent`: equal, or within 2 units in the last
// place of `sent` (the spacing of f32 values just above |sent|), as docs/API.md "Binary" bounds a
// one-channel part's value times its tint.
inline bool withinTwoUlps(float decoded, float sent) {
  if (decoded == sent) return true;
  const float magnitude = std::fabs(sent);
  const double ulp = double(std::nextafter(magnitude, INFINITY)) - double(magnitude);
  return std::fabs(double(decoded) - double(sent)) <= 2 * ulp;
}

inline BinaryMesh parseBinary(const std::string& bytes) {
  size_t at = 0;
  auto take = [&](void* out, size_t n) {
    if (at + n > bytes.size())
      throw std::runtime_error("binary mesh truncated at byte " + std::to_string(at));
    if (n > 0) std::memcpy(out, bytes.data() + at, n);  // an empty part's arrays: out may be null
    at += n;
  };
  auto u32 = [&] {
    uint32_t v;
    take(&v, 4);
    return v;
  };
  auto i32 = [&] {
    int32_t v;
    take(&v, 4);
    return v;
  };
  auto f32 = [&] {
    float v;
    take(&v, 4);
    return v;
  };
  auto align = [&] { at = (at + 3) / 4 * 4; };
  // C·V floats, r, g, b per vertex when C = 3, else each value times the tint in f32.
  auto irradiance = [&](uint32_t channels, const float tint[3], uint32_t vertices) {
    if (channels != 1 && channels != 3) throw std::runtime_error("a part has neither 1 nor 3 channels");
    std::vector<float> sent(channels * size_t(vertices));
    take(sent.data(), 4 * sent.size());
    if (channels == 3) return sent;
    std::vector<float> rgb;
    for (float v : sent)
      for (int c = 0; c < 3; ++c) rgb.push_back(v * tint[c]);
    return rgb;
  };
  BinaryMesh m;
  char magic[4];
  take(magic, 4);
  if (std::string(magic, 4) != "PNMB") throw std::runtime_error("bad magic");
  m.layout = u32(), m.version = u32(), m.flags = u32(), m.since = u32();
  if (m.layout != 4) throw std::runtime_error("binary mesh layout " + std::to_string(m.layout) + ", not 4");
  const uint32_t objects = u32(), parts = u32(), removed = u32();
  m.totalVertices = u32(), m.totalTriangles = u32();
  const uint32_t valueParts = u32();
  if (at != 44) throw std::runtime_error("binary mesh header is not 44 bytes");
  for (uint32_t i = 0; i < objects; ++i) {
    const uint32_t length = u32();
    std::string name(length, '\0');
    take(name.data(), length);
    align();
    m.objects.push_back(name);
  }
  m.parts.resize(parts);
  for (auto& r : m.parts) {
    r.object = u32(), r.face = u32(), r.x = i32(), r.y = i32();
    r.vertices = u32(), r.triangles = u32(), r.version = u32();
    for (float& n : r.normal) n = f32();
    r.channels = u32();
    for (float& t : r.tint) t = f32();
  }
  m.valueParts.resize(valueParts);
  for (auto& r : m.valueParts) {
    r.object = u32(), r.face = u32(), r.x = i32(), r.y = i32(), r.vertices = u32(),
    r.version = u32(), r.channels = u32();
    for (float& t : r.tint) t = f32();
  }
  for (uint32_t i = 0; i < removed; ++i) {
    BinaryMesh::Removed& gone = m.removed.emplace_back();
    gone.object = u32(), gone.face = u32(), gone.x = i32(), gone.y = i32();
  }
  for (auto& r : m.parts) {
    if (at % 4) throw std::runtime_error("a part's arrays are not 4-byte aligned");
    r.positions.resize(3 * r.vertices);
    take(r.positions.data(), 4 * r.positions.size());
    r.irradiance = irradiance(r.channels, r.tint, r.vertices);
    if (m.flags & 2) {  // indirect irradiance, r, g, b per vertex
      r.indirect.resize(3 * size_t(r.vertices));
      take(r.indirect.data(), 4 * r.indirect.size());
    }
    r.classes.resize(r.vertices);
    take(r.classes.data(), r.vertices);
    align();
    r.indices.resize(3 * r.triangles);
    take(r.indices.data(), 4 * r.indices.size());
  }
  for (auto& r : m.valueParts) r.irradiance = irradiance(r.channels, r.tint, r.vertices);
  if (at != bytes.size()) throw std::runtime_error("binary mesh has trailing bytes");
  return m;
}

}  // namespace penumbra::server::test
