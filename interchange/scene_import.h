// The one entry point for bringing a file made elsewhere in: chooses the reader
// by the file's extension (OBJ, glTF, GLB). Free functions; thread-safe.
// The server's "create scene from a file" calls importSceneBytes.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "interchange/gltf_import.h"
#include "interchange/obj_import.h"

namespace penumbra::interchange {

// ".obj", ".gltf" or ".glb" (any case); anything else is a ValidationError at path "(import)".
ImportResult importSceneFile(const std::string& path, const ImportOptions& options);

// An upload: `fileName` picks the reader by its extension; for OBJ, `mtlFiles`
// holds the MTL texts by the names its 'mtllib' lines use.
ImportResult importSceneBytes(const std::vector<uint8_t>& bytes, const std::string& fileName,
                              const std::map<std::string, std::string>& mtlFiles, const ImportOptions& options);

}  // namespace penumbra::interchange
