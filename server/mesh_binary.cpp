#include "server/mesh_binary.h"

#include <bit>
#include <cstring>
#include <map>
#include <stdexcept>

#include "server/tinted_irradiance.h"

namespace penumbra::server::mesh_binary {

namespace {

static_assert(std::endian::native == std::endian::little,
              "the binary mesh is written little-endian");

// Appends fixed-width values; every section keeps the 4-byte alignment typed arrays need.
class Writer {
 public:
  explicit Writer(size_t reserve) { bytes_.reserve(reserve); }
  void u32(uint64_t value) {
    if (value > UINT32_MAX) throw std::overflow_error("binary mesh: value does not fit 32 bits");
    put(static_cast<uint32_t>(value));
  }
  void i32(int64_t value) {
    if (value < INT32_MIN || value > INT32_MAX) throw std::overflow_error("binary mesh: value does not fit 32 bits");
    put(static_cast<int32_t>(value));
  }
  void f32(double value) { put(static_cast<float>(value)); }
  void u8(uint8_t value) { bytes_.push_back(static_cast<char>(value)); }
  void raw(const void* data, size_t size) { bytes_.append(static_cast<const char*>(data), size); }
  void padTo4() {
    while (bytes_.size() % 4) bytes_.push_back('\0');
  }
  std::string take() { return std::move(bytes_); }

 private:
  template <class T>
  void put(T value) {
    char out[sizeof(T)];
    std::memcpy(out, &value, sizeof(T));
    bytes_.append(out, sizeof(T));
  }
  std::string bytes_;
};

uint8_t classCode(LightClass c) {
  switch (c) {
    case LightClass::Lit:
      return kLit;
    case LightClass::Penumbra:
      return kPenumbra;
    case LightClass::Umbra:
      return kUmbra;
  }
  return kLit;
}

// A part's vertices' indirect irradiance: its run of its receiver's vertices in the bake.
void writeIndirect(Writer& out, const IndirectBake& bake, const SceneSnapshot& snapshot, size_t part) {
  const size_t count = snapshot.parts[part].mesh->positions.size();
  const std::vector<Vec3>& e = bake.mesh.receivers.at(bake.partReceiver[part]).irradiance;
  for (size_t v = bake.partOffset[part]; v < bake.partOffset[part] + count; ++v)
    for (int c = 0; c < 3; ++c) out.f32(e.at(v)[c]);
}

// A record's part: u32 object (its name's index), u32 face, i32 chunk x, i32 chunk y.
void writeKey(Writer& out, uint32_t object, const PartKey& key) {
  out.u32(object);
  out.u32(key.receiver.face);
  out.i32(key.x);
  out.i32(key.y);
}

// A record's irradiance fields: u32 channels C, f32 tint[3].
void writeTint(Writer& out, const TintedIrradiance& e) {
  out.u32(e.channels);
  for (float t : e.tint) out.f32(t);
}

}  // namespace

std::string encode(const SceneSnapshot& snapshot, const MeshSelection& selection, const IndirectBake* indirect) {
  // Object names: each named once, parts refer to them by index.
  std::vector<std::string> names;
  std::map<std::string, uint32_t> nameIndex;
  auto indexOf = [&](const std::string& name) {
    const auto [it, inserted] = nameIndex.emplace(name, uint32_t(names.size()));
    if (inserted) names.push_back(name);
    return it->second;
  };
  std::vector<uint32_t> partObjects, valueObjects, removedObjects;
  std::vector<TintedIrradiance> partValues, valueValues;  // each part's irradiance as sent
  size_t vertices = 0, triangles = 0, irradianceFloats = 0;
  for (size_t i : selection.parts) {
    const MeshPart& part = snapshot.parts[i];
    partObjects.push_back(indexOf(part.key.receiver.object));
    partValues.push_back(tintIrradiance(part.mesh->irradiance));
    vertices += part.mesh->positions.size();
    triangles += part.mesh->triangles.size();
    irradianceFloats += partValues.back().values.size();
  }
  for (size_t i : selection.valueParts) {
    valueObjects.push_back(indexOf(snapshot.parts[i].key.receiver.object));
    valueValues.push_back(tintIrradiance(snapshot.parts[i].mesh->irradiance));
    irradianceFloats += valueValues.back().values.size();
  }
  for (const PartKey& key : selection.removedParts) removedObjects.push_back(indexOf(key.receiver.object));

  size_t namesBytes = 0;
  for (const std::string& n : names) namesBytes += 4 + (n.size() + 3) / 4 * 4;
  // (Each part's classes take up to 3 bytes of padding: 4 per part reserved.)
  Writer out(kHeaderBytes + namesBytes + selection.parts.size() * (kPartRecordBytes + 4) +
             selection.removedParts.size() * kRemovedRecordBytes + vertices * (indirect ? 25 : 13) +
             triangles * 12 + selection.valueParts.size() * kValuePartRecordBytes + irradianceFloats * 4);

  out.raw(kMagic, 4);
  out.u32(kLayoutVersion);
  out.u32(snapshot.version);
  out.u32((selection.since ? kFlagDelta : 0) | (indirect ? kFlagIndirect : 0));
  out.u32(selection.since.value_or(0));
  out.u32(names.size());
  out.u32(selection.parts.size());
  out.u32(selection.removedParts.size());
  out.u32(vertices);
  out.u32(triangles);
  out.u32(selection.valueParts.size());

  for (const std::string& n : names) {
    out.u32(n.size());
    out.raw(n.data(), n.size());
    out.padTo4();
  }
  for (size_t k = 0; k < selection.parts.size(); ++k) {
    const MeshPart& part = snapshot.parts[selection.parts[k]];
    const ReceiverMesh& r = *part.mesh;
    writeKey(out, partObjects[k], part.key);
    out.u32(r.positions.size());
    out.u32(r.triangles.size());
    out.u32(part.version);
    for (int c = 0; c < 3; ++c) out.f32(r.normal[c]);
    writeTint(out, partValues[k]);
  }
  for (size_t k = 0; k < selection.valueParts.size(); ++k) {
    const MeshPart& part = snapshot.parts[selection.valueParts[k]];
    writeKey(out, valueObjects[k], part.key);
    out.u32(part.mesh->positions.size());
    out.u32(part.version);
    writeTint(out, valueValues[k]);
  }
  for (size_t k = 0; k < selection.removedParts.size(); ++k)
    writeKey(out, removedObjects[k], selection.removedParts[k]);
  for (size_t k = 0; k < selection.parts.size(); ++k) {
    const ReceiverMesh& r = *snapshot.parts[selection.parts[k]].mesh;
    for (const Vec3& p : r.positions)
      for (int c = 0; c < 3; ++c) out.f32(p[c]);
    out.raw(partValues[k].values.data(), partValues[k].values.size() * sizeof(float));
    if (indirect) writeIndirect(out, *indirect, snapshot, selection.parts[k]);
    for (LightClass c : r.classes) out.u8(classCode(c));
    out.padTo4();
    for (const auto& t : r.triangles)
      for (uint32_t index : t) out.u32(index);
  }
  for (const TintedIrradiance& e : valueValues) out.raw(e.values.data(), e.values.size() * sizeof(float));
  return out.take();
}

}  // namespace penumbra::server::mesh_binary
