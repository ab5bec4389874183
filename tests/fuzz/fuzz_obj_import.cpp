// Fuzz target: OBJ + MTL import (interchange::importObjText through tinyobjloader). The input
// is the OBJ text, then optionally a line "#==MTL==" and the text of "m.mtl" (seeds say
// `mtllib m.mtl`). Refusals (ValidationError) are fine; a scene that comes out must be valid
// scene JSON that reads back.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include "fuzz_support.h"
#include "interchange/obj_import.h"
#include "protocol/scene_json.h"

using namespace penumbra;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 64 * 1024) return 0;  // bounded: one input runs in milliseconds
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::string separator = "#==MTL==\n";
  std::string obj = input;
  std::map<std::string, std::string> mtl;
  if (const size_t at = input.find(separator); at != std::string::npos) {
    obj = input.substr(0, at);
    mtl["m.mtl"] = input.substr(at + separator.size());
  }
  try {
    const interchange::ImportResult result = interchange::importObjText(obj, mtl, {}, "fuzz.obj");
    fuzz::checkImport(result);
  } catch (const protocol::ValidationError& e) {
    fuzz::note(std::string("refused: ") + e.what());
  }
  return 0;
}
