#include "interchange/gltf_extensions.h"

#include <algorithm>
#include <array>

#include <nlohmann/json.hpp>

#include <draco/compression/decode.h>

#include "interchange/gltf_json_edit.h"
#include "interchange/gltf_meshopt.h"
#include "protocol/validation_error.h"

namespace penumbra::interchange {

using protocol::ValidationError;

namespace {

// Required extensions the importer reads: geometry storage it decodes, and what only concerns
// what is not imported (textures are never decoded; unlit and emissive strength are factors).
constexpr std::array kReadable = {
    "KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_mesh_quantization", "KHR_materials_unlit",
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
                                ", which Penumbra does not read (it reads KHR_draco_mesh_compression, "
                                "EXT_meshopt_compression and KHR_mesh_quantization)");
  }
}

namespace {

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

bool mentions(const std::vector<uint8_t>& bytes, const std::string& name) {
  return std::search(bytes.begin(), bytes.end(), name.begin(), name.end()) != bytes.end();
}

}  // namespace

std::vector<uint8_t> readableByTinygltf(const std::vector<uint8_t>& bytes) {
  const bool draco = mentions(bytes, "KHR_draco_mesh_compression");
  const bool meshopt = mentions(bytes, "EXT_meshopt_compression");
  if (!draco && !meshopt) return bytes;
  return editGltfJson(bytes, [&](nlohmann::json& gltf) {
    const bool dropped = draco && dropDracoIndices(gltf);
    const bool placeheld = meshopt && placeholdMeshoptFallbacks(gltf);
    return dropped || placeheld;
  });
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
