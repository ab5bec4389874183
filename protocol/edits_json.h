// Edit scripts (SCENE_FORMAT.md "Edit scripts") <-> penumbra::Frame: a validating
// frame reader naming `edits[i].key.path`, a line-numbered .edits.jsonl reader, and
// an exact writer. Free functions; thread-safe (no shared state).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "core/engine/frame.h"
#include "core/scene/scene.h"
#include "protocol/validation_error.h"
#include "protocol/volume_json.h"

namespace penumbra::protocol {

// One frame: {"edits": [{"op": "move"|"add"|"remove"|"set_light"|"add_light"|
// "remove_light"|"set_volume"|"add_volume"|"set_material", ...}, ...]}. Throws ValidationError at the first
// problem with the path inside the frame (e.g. `edits[1].transform.scale`,
// `edits[0].light.polygon[2]`): unknown op, missing keys, wrong types, non-finite numbers, zero
// scale, an invalid object or light, a light polygon that is not planar and convex, a negative
// radiance, a set_light with neither. With `materials`, an added object's material must be one of
// them; with nullptr, material names are left to Engine::apply. Ids that must (not) exist are the
// engine's check (EditError). add_volume reads its volume's file through `files` (volume_json.h);
// without them it is refused at `edits[i].volume.file`, and the server passes only the files it
// holds (VolumeFiles::onlyKnown): a client cannot make it open any other. A set_volume's isovalue
// range and a move's target (object or volume) are the engine's check. A set_material's material
// is read as a scene's materials[id] (material_json.h); the frame's later edits may name it.
Frame frameFromJson(const nlohmann::json& value, const std::vector<Material>* materials = nullptr,
                    const VolumeFiles* files = nullptr);

// Writes a frame so that frameFromJson(frameToJson(f)) == f.
nlohmann::json frameToJson(const Frame& frame);

// A script refused at one line: what() is "line 7: edits[0].id: problem".
class EditScriptError : public ValidationError {
 public:
  EditScriptError(size_t line, std::string path, std::string problem);
  size_t line() const { return line_; }
  const char* what() const noexcept override { return message_.c_str(); }

 private:
  size_t line_;
  std::string message_;
};

// The engine's refusal of the frame read from `line` (unknown id, duplicate
// add id, ...), with that line: "line 3: edits[0].id: unknown object 'x'".
EditScriptError atLine(size_t line, const EditError& error);

struct ScriptFrame {
  size_t line = 0;  // 1-based line of the frame in the script
  Frame frame;
};

// .edits.jsonl: one frame per line, blank lines allowed. Reads every line before
// returning; throws EditScriptError at the first bad one (path `(json)` for text
// that is not a JSON document). Each line obeys protocol/json_text.h limits.
std::vector<ScriptFrame> readEditScriptFrames(std::string_view text,
                                              const std::vector<Material>* materials = nullptr,
                                              const VolumeFiles* files = nullptr);
std::vector<Frame> readEditScript(std::string_view text,
                                  const std::vector<Material>* materials = nullptr);

// One compact line per frame, each ending in '\n'.
std::string writeEditScript(const std::vector<Frame>& frames);

}  // namespace penumbra::protocol
