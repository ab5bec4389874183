// glTF 2.0 (.gltf with its buffers, or binary .glb) → scene v1 through tinygltf:
// each mesh primitive of each node in the default scene becomes an object (node
// transforms applied, triangles joined back into convex faces), baseColorFactor (times a
// base colour texture's average, texture_average.h) → albedo, emissiveFactor ×
// KHR_materials_emissive_strength → area lights; Penumbra's own GLB back into its scene
// (penumbra_extras.h).
// Free functions; thread-safe (no shared state).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "interchange/scene_assembly.h"

namespace penumbra::interchange {

// Binary when the file starts with the GLB magic "glTF", JSON otherwise; external
// buffers are read beside the file. Images are decoded only within kMaxTexturePixels. Throws
// protocol::ValidationError (path "(gltf)" or a glTF key path) for bad input,
// std::runtime_error when the file cannot be read.
ImportResult importGltfFile(const std::string& path, const ImportOptions& options);

// From memory (an upload): a GLB, or a .gltf whose buffers are data: URIs.
ImportResult importGltfBytes(const std::vector<uint8_t>& bytes, const ImportOptions& options,
                             const std::string& sourceName);

}  // namespace penumbra::interchange
