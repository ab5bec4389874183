// Fuzz target: scene JSON text → protocol::parseJsonText → sceneFromJson, then the writer's
// round trip (sceneToJson of the scene read back is the same document). Refusals
// (ValidationError) are fine; anything else that escapes, or a sanitizer report, is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.h"
#include "protocol/json_text.h"
#include "protocol/scene_json.h"

using namespace penumbra;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  nlohmann::json root;
  try {
    root = protocol::parseJsonText(text, protocol::kMaxJsonFileBytes, protocol::kMaxJsonDepth);
  } catch (const protocol::ValidationError& e) {
    fuzz::note(std::string("refused: ") + e.what());
    return 0;
  }
  Scene scene;
  try {
    scene = protocol::sceneFromJson(root);
  } catch (const protocol::ValidationError& e) {
    fuzz::note(std::string("refused: ") + e.what());
    return 0;
  }
  const nlohmann::json written = protocol::sceneToJson(scene);
  const std::string dumped = written.dump();  // throws (a finding) on invalid UTF-8
  const Scene again = protocol::sceneFromJson(protocol::parseJsonText(dumped, dumped.size(), protocol::kMaxJsonDepth));
  fuzz::check(protocol::sceneToJson(again) == written, "scene JSON round trip differs");
  return 0;
}
