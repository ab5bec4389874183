#include "interchange/gltf_json_edit.h"

#include <cstring>
#include <string>

#include "protocol/validation_error.h"

namespace penumbra::interchange {

using protocol::ValidationError;

namespace {

constexpr uint32_t kJsonChunk = 0x4E4F534Au;  // "JSON", little-endian

uint32_t u32At(const std::vector<uint8_t>& bytes, size_t at) {
  uint32_t v;
  std::memcpy(&v, bytes.data() + at, 4);
  return v;
}
void putU32(std::vector<uint8_t>& bytes, uint32_t v) {
  const auto* p = reinterpret_cast<const uint8_t*>(&v);
  bytes.insert(bytes.end(), p, p + 4);
}

}  // namespace

std::vector<uint8_t> editGltfJson(const std::vector<uint8_t>& bytes,
                                  const std::function<bool(nlohmann::json&)>& edit) {
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (!binary) {
    nlohmann::json gltf = nlohmann::json::parse(bytes.begin(), bytes.end(), nullptr, false);
    if (gltf.is_discarded()) throw ValidationError("(gltf)", "the glTF JSON does not parse");
    if (!edit(gltf)) return bytes;
    const std::string text = gltf.dump();
    return std::vector<uint8_t>(text.begin(), text.end());
  }
  // GLB: a 12-byte header, a JSON chunk, then any other chunks (the BIN chunk), kept as they are.
  if (bytes.size() < 20) throw ValidationError("(gltf)", "the GLB is shorter than its header");
  const uint32_t jsonLength = u32At(bytes, 12);
  if (u32At(bytes, 16) != kJsonChunk || 20 + size_t(jsonLength) > bytes.size())
    throw ValidationError("(gltf)", "the GLB's first chunk is not its JSON");
  nlohmann::json gltf = nlohmann::json::parse(
      bytes.begin() + 20, bytes.begin() + 20 + long(jsonLength), nullptr, false);
  if (gltf.is_discarded()) throw ValidationError("(gltf)", "the GLB's JSON does not parse");
  if (!edit(gltf)) return bytes;
  std::string text = gltf.dump();
  while (text.size() % 4) text.push_back(' ');
  std::vector<uint8_t> out(bytes.begin(), bytes.begin() + 12);
  putU32(out, uint32_t(text.size()));
  putU32(out, kJsonChunk);
  out.insert(out.end(), text.begin(), text.end());
  out.insert(out.end(), bytes.begin() + 20 + long(jsonLength), bytes.end());
  const uint32_t total = uint32_t(out.size());
  std::memcpy(out.data() + 8, &total, 4);
  return out;
}

}  // namespace penumbra::interchange
