#include "interchange/gltf_extensions.h"

#include <algorithm>
#include <array>
#include <cstring>

#include <nlohmann/json.hpp>

#include <draco/compression/decode.h>

#include "protocol/validation_error.h"

namespace penumbra::interchange {

using protocol::ValidationError;

namespace {

// Required extensions the importer reads: geometry storage it decodes, and what only concerns
// what is not imported (textures are never decoded; unlit and emissive strength are factors).
constexpr std::array kReadable = {
    "KHR_draco_mesh_compression", "KHR_mesh_quantization", "KHR_materials_unlit",
    "KHR_materials_emissive_strength", "KHR_texture_transform", "KHR_texture_basisu",
    "EXT_texture_webp", "EXT_texture_avif",
};

}  // namespace

void checkRequiredExtensions(const tinygltf::Model& model) {
  for (size_t i = 0; i < model.extensionsRequired.size(); ++i) {
    const std::string& name = model.extensionsRequired[i];
    if (std::find(kReadable.begin(), kReadable.end(), name) == kReadable.end())
      throw ValidationError("extensionsRequired[" + std::to_string(i) + "]",
                            "the file requires the glTF extension " + name +
                                ", which Penumbra does not read (it reads KHR_draco_mesh_compression and "
                                "KHR_mesh_quantization)");
  }
}

namespace {

uint32_t u32At(const std::vector<uint8_t>& bytes, size_t at) {
  uint32_t v;
  std::memcpy(&v, bytes.data() + at, 4);
  return v;
}
void putU32(std::vector<uint8_t>& bytes, uint32_t v) {
  const auto* p = reinterpret_cast<const uint8_t*>(&v);
  bytes.insert(bytes.end(), p, p + 4);
}

// Drops `indices` from every Draco primitive of the glTF JSON; whether any was dropped.
bool dropDracoIndices(nlohmann::json& gltf) {
  bool changed = false;
  if (!gltf.contains("meshes") || !gltf["meshes"].is_array()) return false;
  for (nlohmann::json& mesh : gltf["meshes"]) {
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (nlohmann::json& primitive : mesh["primitives"])
      if (primitive.is_object() && primitive.contains("extensions") && primitive["extensions"].is_object() &&
          primitive["extensions"].contains("KHR_draco_mesh_compression") && primitive.contains("indices")) {
        primitive.erase("indices");
        changed = true;
      }
  }
  return changed;
}

}  // namespace

std::vector<uint8_t> withoutDracoIndices(const std::vector<uint8_t>& bytes) {
  static const std::string kName = "KHR_draco_mesh_compression";
  if (std::search(bytes.begin(), bytes.end(), kName.begin(), kName.end()) == bytes.end()) return bytes;
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (!binary) {
    nlohmann::json gltf = nlohmann::json::parse(bytes.begin(), bytes.end(), nullptr, false);
    if (gltf.is_discarded()) throw ValidationError("(gltf)", "the glTF JSON does not parse");
    if (!dropDracoIndices(gltf)) return bytes;
    const std::string text = gltf.dump();
    return std::vector<uint8_t>(text.begin(), text.end());
  }
  // GLB: a 12-byte header, a JSON chunk, then any other chunks (the BIN chunk), kept as they are.
  if (bytes.size() < 20) throw ValidationError("(gltf)", "the GLB is shorter than its header");
  const uint32_t jsonLength = u32At(bytes, 12);
  if (u32At(bytes, 16) != 0x4E4F534Au || 20 + size_t(jsonLength) > bytes.size())
    throw ValidationError("(gltf)", "the GLB's first chunk is not its JSON");
  nlohmann::json gltf =
      nlohmann::json::parse(bytes.begin() + 20, bytes.begin() + 20 + long(jsonLength), nullptr, false);
  if (gltf.is_discarded()) throw ValidationError("(gltf)", "the GLB's JSON does not parse");
  if (!dropDracoIndices(gltf)) return bytes;
  std::string text = gltf.dump();
  while (text.size() % 4) text.push_back(' ');
  std::vector<uint8_t> out(bytes.begin(), bytes.begin() + 12);
  putU32(out, uint32_t(text.size()));
  putU32(out, 0x4E4F534Au);
  out.insert(out.end(), text.begin(), text.end());
  out.insert(out.end(), bytes.begin() + 20 + long(jsonLength), bytes.end());
  const uint32_t total = uint32_t(out.size());
  std::memcpy(out.data() + 8, &total, 4);
  return out;
}

std::optional<DecodedPrimitive> decodeDracoPrimitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                                     const std::string& path) {
  const auto extension = primitive.extensions.find("KHR_draco_mesh_compression");
  if (extension == primitive.extensions.end()) return std::nullopt;
  const std::string where = path + ".extensions.KHR_draco_mesh_compression";
  const tinygltf::Value& draco = extension->second;
  const int view = draco.Has("bufferView") ? draco.Get("bufferView").GetNumberAsInt() : -1;
  if (view < 0 || size_t(view) >= model.bufferViews.size()) throw ValidationError(where + ".bufferView", "no such buffer view");
  const tinygltf::BufferView& bufferView = model.bufferViews[size_t(view)];
  if (bufferView.buffer < 0 || size_t(bufferView.buffer) >= model.buffers.size() ||
      bufferView.byteOffset + bufferView.byteLength > model.buffers[size_t(bufferView.buffer)].data.size())
    throw ValidationError(where + ".bufferView", "the buffer view runs past its buffer");
  if (!draco.Get("attributes").Has("POSITION")) throw ValidationError(where + ".attributes", "no POSITION");
  const int positionId = draco.Get("attributes").Get("POSITION").GetNumberAsInt();
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  if (mode != TINYGLTF_MODE_TRIANGLES) throw ValidationError(path + ".mode", "a Draco primitive must be triangles");

  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(model.buffers[size_t(bufferView.buffer)].data.data() + bufferView.byteOffset),
              bufferView.byteLength);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) throw ValidationError(where, "the Draco stream does not decode: " + decoded.status().error_msg_string());
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  const draco::PointAttribute* position = mesh->GetAttributeByUniqueId(uint32_t(positionId));
  if (!position || position->num_components() != 3)
    throw ValidationError(where + ".attributes.POSITION", "the Draco stream has no 3-component attribute " +
                                                              std::to_string(positionId));
  DecodedPrimitive out;
  out.positions.reserve(mesh->num_points());
  for (draco::PointIndex i(0); i < mesh->num_points(); ++i) {
    std::array<float, 3> v{};
    position->ConvertValue<float, 3>(position->mapped_index(i), v.data());
    out.positions.push_back(Vec3(v[0], v[1], v[2]));
  }
  out.triangles.reserve(mesh->num_faces());
  for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
    const draco::Mesh::Face& face = mesh->face(f);
    out.triangles.push_back({int(face[0].value()), int(face[1].value()), int(face[2].value())});
  }
  return out;
}

}  // namespace penumbra::interchange
