#include "protocol/edits_json.h"

#include <optional>

#include "protocol/json_reader.h"
#include "protocol/json_text.h"
#include "protocol/material_json.h"
#include "protocol/scene_json.h"
#include "protocol/volume_json.h"

namespace penumbra::protocol {

namespace {

constexpr std::string_view kOps =
    "expected \"move\", \"add\", \"remove\", \"set_light\", \"add_light\", \"remove_light\", "
    "\"set_volume\", \"add_volume\" or \"set_material\"";

// Without a material list, any named material passes here (Engine::apply checks
// it against the scene); every other object check still runs.
std::vector<Material> materialsFor(const Json& object, const std::vector<Material>* materials) {
  if (materials) return *materials;
  std::vector<Material> named;
  if (object.is_object())
    if (const Json* m = optionalKey(object, "material"); m && m->is_string())
      named.push_back(Material{m->get<std::string>(), Vec3(0.8)});
  return named;
}

Edit editFromJson(const Json& value, const std::string& path,
                  const std::vector<Material>* materials, const VolumeFiles* files) {
  expectObject(value, path);
  const std::string op = expectString(requireKey(value, "op", path), keyPath(path, "op"));
  Edit edit;
  if (op == "move") {
    edit.op = Edit::Op::Move;
    edit.id = expectName(requireKey(value, "id", path), keyPath(path, "id"));
    edit.transform =
        transformFromJson(requireKey(value, "transform", path), keyPath(path, "transform"));
  } else if (op == "remove") {
    edit.op = Edit::Op::Remove;
    edit.id = expectName(requireKey(value, "id", path), keyPath(path, "id"));
  } else if (op == "add") {
    edit.op = Edit::Op::Add;
    const Json& object = requireKey(value, "object", path);
    edit.object = objectFromJson(object, keyPath(path, "object"), materialsFor(object, materials));
    edit.id = edit.object.id;
  } else if (op == "set_light") {
    edit.op = Edit::Op::SetLight;
    edit.id = expectName(requireKey(value, "id", path), keyPath(path, "id"));
    if (const Json* polygon = optionalKey(value, "polygon"))
      edit.polygon = lightPolygonFromJson(*polygon, keyPath(path, "polygon"));
    if (const Json* radiance = optionalKey(value, "radiance"))
      edit.radiance = radianceFromJson(*radiance, keyPath(path, "radiance"));
    if (!edit.polygon && !edit.radiance)
      fail(path, "set_light changes nothing: give \"polygon\", \"radiance\" or both");
  } else if (op == "add_light") {
    edit.op = Edit::Op::AddLight;
    edit.light = lightFromJson(requireKey(value, "light", path), keyPath(path, "light"));
    edit.id = edit.light.id;
  } else if (op == "remove_light") {
    edit.op = Edit::Op::RemoveLight;
    edit.id = expectName(requireKey(value, "id", path), keyPath(path, "id"));
  } else if (op == "set_volume") {
    edit.op = Edit::Op::SetVolume;
    edit.id = expectName(requireKey(value, "id", path), keyPath(path, "id"));
    edit.isovalue = expectNumber(requireKey(value, "isovalue", path), keyPath(path, "isovalue"));
  } else if (op == "add_volume") {
    edit.op = Edit::Op::AddVolume;
    const Json& volume = requireKey(value, "volume", path);
    const std::string where = keyPath(path, "volume");
    if (!isVolumeObject(volume, where))
      fail(keyPath(where, "type"), "missing: \"type\": \"volume\"");
    edit.volume = volumeFromJson(volume, where, materialsFor(volume, materials), files);
    edit.id = edit.volume.id;
  } else if (op == "set_material") {
    edit.op = Edit::Op::SetMaterial;
    edit.id = expectName(requireKey(value, "id", path), keyPath(path, "id"));
    edit.material =
        materialFromJson(edit.id, requireKey(value, "material", path), keyPath(path, "material"));
  } else {
    fail(keyPath(path, "op"), "unknown op '" + op + "' (" + std::string(kOps) + ")");
  }
  return edit;
}

}  // namespace

Frame frameFromJson(const Json& value, const std::vector<Material>* materials,
                    const VolumeFiles* files) {
  expectObject(value, "");
  const Json& edits = expectArray(requireKey(value, "edits", ""), "edits");
  Frame frame;
  // The materials as the frame's earlier set_material edits leave them (an object added after one
  // may name it).
  std::optional<std::vector<Material>> known;
  if (materials) known = *materials;
  for (size_t i = 0; i < edits.size(); ++i) {
    frame.edits.push_back(
        editFromJson(edits[i], indexPath("edits", i), known ? &*known : nullptr, files));
    const Edit& edit = frame.edits.back();
    if (known && edit.op == Edit::Op::SetMaterial) {
      std::erase_if(*known, [&](const Material& m) { return m.id == edit.id; });
      known->push_back(edit.material);
    }
  }
  return frame;
}

Json frameToJson(const Frame& frame) {
  Json edits = Json::array();
  for (const Edit& edit : frame.edits) {
    switch (edit.op) {
      case Edit::Op::Move:
        edits.push_back(
            {{"op", "move"}, {"id", edit.id}, {"transform", transformToJson(edit.transform)}});
        break;
      case Edit::Op::Add:
        edits.push_back({{"op", "add"}, {"object", objectToJson(edit.object)}});
        break;
      case Edit::Op::Remove:
        edits.push_back({{"op", "remove"}, {"id", edit.id}});
        break;
      case Edit::Op::SetLight: {
        Json light{{"op", "set_light"}, {"id", edit.id}};
        if (edit.polygon) light["polygon"] = polygonToJson(*edit.polygon);
        if (edit.radiance) light["radiance"] = toJson(*edit.radiance);
        edits.push_back(std::move(light));
        break;
      }
      case Edit::Op::AddLight:
        edits.push_back({{"op", "add_light"}, {"light", lightToJson(edit.light)}});
        break;
      case Edit::Op::RemoveLight:
        edits.push_back({{"op", "remove_light"}, {"id", edit.id}});
        break;
      case Edit::Op::SetVolume:
        edits.push_back({{"op", "set_volume"}, {"id", edit.id}, {"isovalue", edit.isovalue}});
        break;
      case Edit::Op::AddVolume:
        edits.push_back({{"op", "add_volume"}, {"volume", volumeToJson(edit.volume)}});
        break;
      case Edit::Op::SetMaterial:
        edits.push_back({{"op", "set_material"},
                         {"id", edit.id},
                         {"material", materialToJson(edit.material)}});
        break;
    }
  }
  return Json{{"edits", std::move(edits)}};
}

EditScriptError::EditScriptError(size_t line, std::string path, std::string problem)
    : ValidationError(path, problem), line_(line) {
  message_ =
      "line " + std::to_string(line) + ": " + (path.empty() ? problem : path + ": " + problem);
}

EditScriptError atLine(size_t line, const EditError& error) {
  return EditScriptError(line, error.keyPath(), error.problem());
}

std::vector<ScriptFrame> readEditScriptFrames(std::string_view text,
                                              const std::vector<Material>* materials,
                                              const VolumeFiles* files) {
  std::vector<ScriptFrame> frames;
  size_t line = 0;
  for (size_t start = 0; start < text.size();) {
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view content = text.substr(start, end - start);
    start = end + 1;
    ++line;
    if (!content.empty() && content.back() == '\r') content.remove_suffix(1);
    if (content.find_first_not_of(" \t") == std::string_view::npos) continue;  // blank line
    try {
      frames.push_back(
          {line, frameFromJson(parseJsonText(content, kMaxJsonFileBytes, kMaxJsonDepth), materials,
                               files)});
    } catch (const ValidationError& error) {
      throw EditScriptError(line, error.path(), error.problem());
    }
  }
  return frames;
}

std::vector<Frame> readEditScript(std::string_view text, const std::vector<Material>* materials) {
  std::vector<Frame> frames;
  for (ScriptFrame& f : readEditScriptFrames(text, materials)) frames.push_back(std::move(f.frame));
  return frames;
}

std::string writeEditScript(const std::vector<Frame>& frames) {
  std::string text;
  for (const Frame& frame : frames) text += frameToJson(frame).dump() + "\n";
  return text;
}

}  // namespace penumbra::protocol
