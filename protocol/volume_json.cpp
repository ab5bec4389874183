#include "protocol/volume_json.h"

#include <algorithm>
#include <filesystem>

#include "core/geom/resource_limit.h"
#include "protocol/json_reader.h"
#include "protocol/scene_json.h"

namespace penumbra::protocol {

namespace {

// Polygon keys on a volume are a mistake worth naming (they would otherwise be ignored).
constexpr const char* kPolygonKeys[] = {"vertices", "faces", "static"};

std::string resolve(const std::string& file, const VolumeFiles& files) {
  std::filesystem::path path(file);
  if (path.is_relative() && !files.baseDirectory.empty())
    path = std::filesystem::path(files.baseDirectory) / path;
  std::error_code error;
  const std::filesystem::path absolute = std::filesystem::absolute(path, error);
  return (error ? path : absolute).lexically_normal().string();
}

std::shared_ptr<const volume::ScalarVolume> readFile(const std::string& file,
                                                     const std::string& resolved,
                                                     const std::string& path,
                                                     const VolumeFiles& files) {
  const std::string where = keyPath(path, "file");
  try {
    return readNrrdVolume(resolved, files.limits);
  } catch (const NrrdError& error) {
    fail(where, "'" + file + "': " + error.what());
  } catch (const ResourceLimitError& error) {
    fail(where,
         "'" + file + "': " + error.what() + " (a volume's header is checked before its data)");
  } catch (const std::bad_alloc&) {
    fail(where, "'" + file + "': not enough memory for the volume");
  }
}

// Inside the server's upload folder (no "..": resolve() normalised it) or one of the listed files.
bool knownFile(const std::string& resolved, const VolumeFiles& files) {
  if (std::find(files.knownFiles.begin(), files.knownFiles.end(), resolved) !=
      files.knownFiles.end())
    return true;
  if (files.knownDirectory.empty()) return false;
  const std::filesystem::path dir = std::filesystem::path(files.knownDirectory).lexically_normal();
  const std::filesystem::path relative = std::filesystem::path(resolved).lexically_relative(dir);
  return !relative.empty() && *relative.begin() != ".." && relative.is_relative() &&
         relative.has_filename() && std::distance(relative.begin(), relative.end()) == 1;
}

}  // namespace

bool isVolumeObject(const Json& value, const std::string& path) {
  expectObject(value, path);
  const Json* type = optionalKey(value, "type");
  if (!type) return false;
  const std::string name = expectString(*type, keyPath(path, "type"));
  if (name != "volume")
    fail(keyPath(path, "type"),
         "unknown object type '" + name + "' (\"volume\", or no type for a polygon object)");
  return true;
}

VolumeObject volumeFromJson(const Json& value, const std::string& path,
                            const std::vector<Material>& materials, const VolumeFiles* files) {
  expectObject(value, path);
  VolumeObject volume;
  volume.id = expectName(requireKey(value, "id", path), keyPath(path, "id"));
  for (const char* key : kPolygonKeys)
    if (optionalKey(value, key))
      fail(keyPath(path, key), std::string("a volume object has no '") + key + "'");
  const std::string file = expectName(requireKey(value, "file", path), keyPath(path, "file"));
  volume.isovalue = expectNumber(requireKey(value, "isovalue", path), keyPath(path, "isovalue"));
  if (const Json* material = optionalKey(value, "material")) {
    volume.material = expectString(*material, keyPath(path, "material"));
    const bool known = std::any_of(materials.begin(), materials.end(),
                                   [&](const Material& m) { return m.id == volume.material; });
    if (!known) fail(keyPath(path, "material"), "unknown material '" + volume.material + "'");
  }
  if (const Json* transform = optionalKey(value, "transform"))
    volume.transform = transformFromJson(*transform, keyPath(path, "transform"));
  // The file last: every cheap check first, and no file is opened for a broken object.
  if (!files)
    fail(keyPath(path, "file"),
         "volume files are read only from scene files (penumbra serve / render "
         "SCENE), not from a scene sent as JSON");
  volume.file = resolve(file, *files);
  if (files->onlyKnown && !knownFile(volume.file, *files))
    fail(keyPath(path, "file"), "'" + file +
                                    "' is not a volume file this server holds: upload it "
                                    "with POST /api/scenes/{id}/volumes");
  volume.data = readFile(file, volume.file, path, *files);
  return volume;
}

Json volumeToJson(const VolumeObject& volume) {
  Json out = Json::object();
  out["id"] = volume.id;
  out["type"] = "volume";
  out["file"] = volume.file;
  out["isovalue"] = volume.isovalue;
  if (!volume.material.empty()) out["material"] = volume.material;
  if (volume.transform != Transform{}) out["transform"] = transformToJson(volume.transform);
  return out;
}

}  // namespace penumbra::protocol
