#include "interchange/scene_import.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "protocol/validation_error.h"

namespace penumbra::interchange {

namespace {

enum class Format { Obj, Gltf };

Format formatOf(const std::string& fileName) {
  std::string extension = std::filesystem::path(fileName).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (extension == ".obj") return Format::Obj;
  if (extension == ".gltf" || extension == ".glb") return Format::Gltf;
  throw protocol::ValidationError("(import)", "cannot import '" + fileName + "': expected .obj, .gltf or .glb");
}

}  // namespace

ImportResult importSceneFile(const std::string& path, const ImportOptions& options) {
  return formatOf(path) == Format::Obj ? importObjFile(path, options) : importGltfFile(path, options);
}

ImportResult importSceneBytes(const std::vector<uint8_t>& bytes, const std::string& fileName,
                              const std::map<std::string, std::string>& mtlFiles, const ImportOptions& options) {
  if (formatOf(fileName) == Format::Obj)
    return importObjText(std::string(bytes.begin(), bytes.end()), mtlFiles, options, fileName);
  return importGltfBytes(bytes, options, fileName);
}

}  // namespace penumbra::interchange
