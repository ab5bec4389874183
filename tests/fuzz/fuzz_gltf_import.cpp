// Fuzz target: glTF (JSON with data: URIs) and GLB import (interchange::importGltfBytes through
// tinygltf). Refusals (ValidationError) are fine; a scene that comes out must be valid scene
// JSON that reads back.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fuzz_support.h"
#include "interchange/gltf_import.h"
#include "protocol/scene_json.h"

using namespace penumbra;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 256 * 1024) return 0;  // bounded: one input runs in milliseconds
  const std::vector<uint8_t> bytes(data, data + size);
  try {
    const interchange::ImportResult result = interchange::importGltfBytes(bytes, {}, "fuzz.glb");
    fuzz::checkImport(result);
  } catch (const protocol::ValidationError& e) {
    fuzz::note(std::string("refused: ") + e.what());
  }
  return 0;
}
