#include "server/utf8_boundary.h"

#include <httplib.h>

#include "server/api_errors.h"

namespace penumbra::server {

namespace {

[[noreturn]] void refuse(const std::string& path, const std::string& what) {
  throw ApiError(400, error_code::kInvalidUtf8, path, what + " is not valid UTF-8");
}

}  // namespace

void requireUtf8Request(const httplib::Request& req) {
  for (const auto& [name, value] : req.params) {
    if (!isValidUtf8(name)) refuse("query." + name, "a query parameter name");
    if (!isValidUtf8(value)) refuse("query." + name, "the value of query parameter '" + name + "'");
  }
  for (const auto& [part, file] : req.files) {
    const std::string path = "(form)." + part;
    if (!isValidUtf8(part)) refuse(path, "a form part name");
    if (!isValidUtf8(file.filename))
      refuse(path + ".filename", "the file name of form part '" + part + "'");
    if (!isValidUtf8(file.content_type))
      refuse(path + ".content_type", "the content type of form part '" + part + "'");
  }
}

std::optional<std::string> invalidUtf8Path(const Scene& scene) {
  const auto at = [](const char* list, size_t i, const char* key) {
    return std::string(list) + "[" + std::to_string(i) + "]." + key;
  };
  for (size_t i = 0; i < scene.lights().size(); ++i)
    if (!isValidUtf8(scene.lights()[i].id)) return at("lights", i, "id");
  for (size_t i = 0; i < scene.materials().size(); ++i)
    if (!isValidUtf8(scene.materials()[i].id)) return at("materials", i, "id");
  for (size_t i = 0; i < scene.objects().size(); ++i) {
    const Object& object = scene.objects()[i];
    if (!isValidUtf8(object.id)) return at("objects", i, "id");
    if (!isValidUtf8(object.material)) return at("objects", i, "material");
  }
  return std::nullopt;
}

}  // namespace penumbra::server
