#include "server/scene_upload.h"

#include <httplib.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "server/api_errors.h"

namespace penumbra::server {

namespace {

const char* const kFormats[] = {"obj", "gltf", "glb"};

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return text;
}

// ".OBJ" → "obj"; "" when the name has no extension we import.
std::string importFormatOf(const std::string& fileName) {
  const std::string extension = lowercase(std::filesystem::path(fileName).extension().string());
  for (const char* format : kFormats)
    if (extension == std::string(".") + format) return format;
  return "";
}

ApiError badParameter(const std::string& name, const std::string& message) {
  return ApiError(400, error_code::kBadParameter, "query." + name, message);
}

// Numbers separated by commas, each finite; empty on any malformed part.
std::vector<double> numberList(const std::string& text) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ',')) {
    try {
      size_t used = 0;
      const double value = std::stod(part, &used);
      if (used != part.size() || !std::isfinite(value)) return {};
      values.push_back(value);
    } catch (const std::exception&) {
      return {};
    }
  }
  return values;
}

interchange::ImportOptions importOptionsOf(const httplib::Request& req) {
  interchange::ImportOptions options;
  if (req.has_param("scale")) {
    const std::string text = req.get_param_value("scale");
    const std::vector<double> value = numberList(text);
    if (value.size() != 1 || !(value[0] > 0))
      throw badParameter("scale", "scale must be one positive number, got '" + text + "'");
    options.scale = value[0];
  }
  if (req.has_param("light_radiance")) {
    const std::string text = req.get_param_value("light_radiance");
    const std::vector<double> value = numberList(text);
    const bool nonNegative =
        std::all_of(value.begin(), value.end(), [](double v) { return v >= 0; });
    if ((value.size() != 1 && value.size() != 3) || !nonNegative)
      throw badParameter(
          "light_radiance",
          "light_radiance must be 'r,g,b' (or one number), each >= 0, got '" + text + "'");
    options.lightRadiance = value.size() == 1 ? Vec3(value[0]) : Vec3(value[0], value[1], value[2]);
  }
  if (req.has_param("studio")) {
    const std::string text = req.get_param_value("studio");
    if (text != "0" && text != "1")
      throw badParameter("studio", "studio must be 1 (a file without lights goes into the default studio, "
                                   "the default) or 0 (such a file is refused), got '" + text + "'");
    options.studio = text == "1";
  }
  return options;
}

// The name the importer sees: the upload's own name when its extension says `format`,
// else that name with ".format" appended (the reader is picked by the extension).
std::string fileNameFor(const std::string& name, const std::string& format) {
  const std::string base =
      name.empty() ? "upload" : std::filesystem::path(name).filename().string();
  return importFormatOf(base) == format ? base : base + "." + format;
}

// 'mtllib' may name a path ("materials/box.mtl") while a browser sends only the file's
// base name: match such names to an uploaded file of the same base name.
void matchMtllibPaths(const std::string& objText, std::map<std::string, std::string>& mtlFiles) {
  std::istringstream lines(objText);
  std::string line;
  std::map<std::string, std::string> byPath;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string keyword, name;
    if (!(words >> keyword) || keyword != "mtllib") continue;
    while (words >> name) {
      if (mtlFiles.count(name)) continue;
      const auto it = mtlFiles.find(std::filesystem::path(name).filename().string());
      if (it != mtlFiles.end()) byPath[name] = it->second;
    }
  }
  mtlFiles.insert(byPath.begin(), byPath.end());
}

}  // namespace

std::optional<SceneUpload> sceneUploadOf(const httplib::Request& req) {
  std::string format = req.has_param("format") ? req.get_param_value("format") : "";
  const bool form = req.is_multipart_form_data();
  if (!format.empty() && format != "scene" && importFormatOf("x." + format) != format)
    throw badParameter("format",
                       "format must be 'scene', 'obj', 'gltf' or 'glb', got '" + format + "'");

  SceneUpload upload;
  std::string uploadName = req.has_param("name") ? req.get_param_value("name") : "";
  if (form) {
    for (const auto& [part, value] : req.files)
      if (part != "file" && part != "mtl")
        throw ApiError(
            400, error_code::kBadRequest, "(form)." + part,
            "unknown form part '" + part + "': send one part 'file' and any number of parts 'mtl'");
    if (req.files.count("file") != 1)
      throw ApiError(400, error_code::kBadRequest, "(form).file",
                     "the form needs exactly one part 'file' (the OBJ, glTF or GLB)");
    const httplib::MultipartFormData file = req.get_file_value("file");
    if (format.empty()) format = importFormatOf(file.filename);
    if (format.empty() || format == "scene")
      throw ApiError(400, error_code::kBadRequest, "(form).file",
                     "cannot tell the format of '" + file.filename +
                         "': name it .obj, .gltf or .glb, or say ?format=obj|gltf|glb "
                         "(scene JSON is sent as the body, not as a form)");
    upload.bytes.assign(file.content.begin(), file.content.end());
    if (uploadName.empty()) uploadName = file.filename;
    const auto [first, last] = req.files.equal_range("mtl");
    for (auto it = first; it != last; ++it) {
      const std::string name = std::filesystem::path(it->second.filename).filename().string();
      if (name.empty() || name == "." || name == "..")
        throw ApiError(400, error_code::kBadRequest, "(form).mtl",
                       "every 'mtl' part needs a file name (the name the OBJ's mtllib line uses)");
      upload.mtlFiles[name] = it->second.content;
    }
  } else {
    if (format.empty() || format == "scene") {
      for (const char* name : {"scale", "light_radiance", "studio"})
        if (req.has_param(name))
          throw badParameter(name, "scale, light_radiance and studio apply to imports only (format=obj|gltf|glb)");
      return std::nullopt;
    }
    upload.bytes.assign(req.body.begin(), req.body.end());
  }
  if (upload.bytes.empty())
    throw ApiError(400, error_code::kBadRequest, form ? "(form).file" : "(body)",
                   "the uploaded file is empty");
  if (!upload.mtlFiles.empty() && format != "obj")
    throw ApiError(400, error_code::kBadRequest, "(form).mtl", "MTL files go with an OBJ only");
  upload.fileName = fileNameFor(uploadName, format);
  if (format == "obj")
    matchMtllibPaths(std::string(upload.bytes.begin(), upload.bytes.end()), upload.mtlFiles);
  upload.options = importOptionsOf(req);
  return upload;
}

}  // namespace penumbra::server
