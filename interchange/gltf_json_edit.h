// A glTF file's JSON edited in place, in either container (GLB chunks or glTF text), for the
// fixes tinygltf needs before it can read a file (gltf_extensions.h) and for tests that write
// files tinygltf's writer cannot. Free function; thread-safe.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <vector>

namespace penumbra::interchange {

// The file with its glTF JSON passed through `edit` (which returns whether it changed anything):
// GLB keeps its other chunks (the BIN chunk) as they are; the file comes back unchanged when
// nothing changed. Throws protocol::ValidationError at "(gltf)" on a GLB container or JSON it
// cannot read.
std::vector<uint8_t> editGltfJson(const std::vector<uint8_t>& bytes,
                                  const std::function<bool(nlohmann::json&)>& edit);

}  // namespace penumbra::interchange
