#include "interchange/gltf_meshopt.h"

#include <meshoptimizer.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "protocol/validation_error.h"

namespace penumbra::interchange {

using protocol::ValidationError;

namespace {

constexpr const char* kExtension = "EXT_meshopt_compression";
constexpr size_t kMaxDecodedBytes = size_t(256) << 20;

bool isFallbackWithoutData(const nlohmann::json& buffer) {
  if (!buffer.is_object() || buffer.contains("uri")) return false;
  const auto extensions = buffer.find("extensions");
  if (extensions == buffer.end() || !extensions->is_object() || !extensions->contains(kExtension))
    return false;
  const nlohmann::json& meshopt = (*extensions)[kExtension];
  return meshopt.is_object() && meshopt.contains("fallback") && meshopt["fallback"] == true;
}

// A non-negative integer member of the extension's object, or `fallback` when absent.
size_t sizeMember(const tinygltf::Value& meshopt, const char* key, const std::string& where,
                  std::optional<size_t> fallback) {
  if (!meshopt.Has(key)) {
    if (!fallback) throw ValidationError(where + "." + key, "missing");
    return *fallback;
  }
  const tinygltf::Value& v = meshopt.Get(key);
  const double x = v.IsNumber() ? v.GetNumberAsDouble() : -1;
  if (!(x >= 0 && x <= 1e15 && x == std::floor(x)))  // 1e15: far past any size, exact as a double
    throw ValidationError(where + "." + key, "must be a non-negative integer");
  return size_t(x);
}

std::string stringMember(const tinygltf::Value& meshopt, const char* key, const std::string& where,
                         const char* fallback) {
  if (!meshopt.Has(key)) return fallback;
  if (!meshopt.Get(key).IsString()) throw ValidationError(where + "." + key, "must be a string");
  return meshopt.Get(key).Get<std::string>();
}

// The view's data, decoded: count × stride bytes.
std::vector<unsigned char> decodeView(const tinygltf::Model& model, const tinygltf::Value& meshopt,
                                      const std::string& where, size_t& decodedSoFar) {
  if (!meshopt.IsObject()) throw ValidationError(where, "must be an object");
  const size_t buffer = sizeMember(meshopt, "buffer", where, std::nullopt);
  if (buffer >= model.buffers.size()) throw ValidationError(where + ".buffer", "no such buffer");
  const std::vector<unsigned char>& source = model.buffers[buffer].data;
  const size_t offset = sizeMember(meshopt, "byteOffset", where, 0);
  const size_t length = sizeMember(meshopt, "byteLength", where, std::nullopt);
  if (offset > source.size() || length > source.size() - offset)
    throw ValidationError(where + ".byteLength",
                          "the compressed bytes run past buffer " + std::to_string(buffer));
  const size_t stride = sizeMember(meshopt, "byteStride", where, std::nullopt);
  const size_t count = sizeMember(meshopt, "count", where, std::nullopt);
  const std::string mode = stringMember(meshopt, "mode", where, "");
  const std::string filter = stringMember(meshopt, "filter", where, "NONE");

  // Each codec's preconditions (the library asserts them) checked first.
  if (mode == "ATTRIBUTES") {
    if (stride == 0 || stride > 256 || stride % 4)
      throw ValidationError(where + ".byteStride",
                            "ATTRIBUTES need a stride of 4 to 256 bytes, a multiple of 4");
  } else if (mode == "TRIANGLES" || mode == "INDICES") {
    if (stride != 2 && stride != 4)
      throw ValidationError(where + ".byteStride", mode + " need a stride of 2 or 4 bytes");
    if (mode == "TRIANGLES" && count % 3)
      throw ValidationError(where + ".count", "TRIANGLES need a multiple of 3 indices");
    if (filter != "NONE") throw ValidationError(where + ".filter", "only ATTRIBUTES are filtered");
  } else {
    throw ValidationError(where + ".mode",
                          "must be ATTRIBUTES, TRIANGLES or INDICES, not '" + mode + "'");
  }
  if ((filter == "OCTAHEDRAL" && stride != 4 && stride != 8) ||
      (filter == "QUATERNION" && stride != 8))
    throw ValidationError(where + ".filter",
                          filter + " does not apply to a stride of " + std::to_string(stride));
  if (filter != "NONE" && filter != "OCTAHEDRAL" && filter != "QUATERNION" &&
      filter != "EXPONENTIAL")
    throw ValidationError(
        where + ".filter",
        "must be NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL, not '" + filter + "'");
  if (count > (kMaxDecodedBytes - decodedSoFar) / stride)
    throw ValidationError(where + ".count", "the file decodes to more than 256 MiB");
  decodedSoFar += count * stride;

  std::vector<unsigned char> out(count * stride);
  const unsigned char* bytes = source.data() + offset;
  const int status =
      mode == "ATTRIBUTES"  ? meshopt_decodeVertexBuffer(out.data(), count, stride, bytes, length)
      : mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out.data(), count, stride, bytes, length)
                            : meshopt_decodeIndexSequence(out.data(), count, stride, bytes, length);
  if (status != 0)
    throw ValidationError(where, "the " + mode + " stream does not decode (meshoptimizer error " +
                                     std::to_string(status) + ")");
  if (filter == "OCTAHEDRAL") meshopt_decodeFilterOct(out.data(), count, stride);
  if (filter == "QUATERNION") meshopt_decodeFilterQuat(out.data(), count, stride);
  if (filter == "EXPONENTIAL") meshopt_decodeFilterExp(out.data(), count, stride);
  return out;
}

}  // namespace

bool placeholdMeshoptFallbacks(nlohmann::json& gltf) {
  if (!gltf.contains("buffers") || !gltf["buffers"].is_array()) return false;
  bool changed = false;
  for (nlohmann::json& buffer : gltf["buffers"])
    if (isFallbackWithoutData(buffer)) {
      buffer["uri"] = "data:application/octet-stream;base64,AAAAAA==";
      buffer["byteLength"] = 4;
      changed = true;
    }
  return changed;
}

size_t decodeMeshoptViews(tinygltf::Model& model) {
  size_t decodedViews = 0, decodedBytes = 0;
  for (size_t i = 0; i < model.bufferViews.size(); ++i) {
    const auto extension = model.bufferViews[i].extensions.find(kExtension);
    if (extension == model.bufferViews[i].extensions.end()) continue;
    const std::string where = "bufferViews[" + std::to_string(i) + "].extensions." + kExtension;
    tinygltf::Buffer decoded;
    decoded.data = decodeView(model, extension->second, where, decodedBytes);
    model.buffers.push_back(std::move(decoded));
    tinygltf::BufferView& view = model.bufferViews[i];
    view.buffer = int(model.buffers.size() - 1);
    view.byteOffset = 0;
    view.byteLength = model.buffers.back().data.size();
    ++decodedViews;
  }
  return decodedViews;
}

}  // namespace penumbra::interchange
