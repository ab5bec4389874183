// What Penumbra's own GLB export carries beyond the display (issue 40, the round trip; written by
// glb_export.cpp, read back by gltf_import.cpp, docs/SCENE_FORMAT.md "GLB round trip"): under the
// key "penumbra" of asset.extras (marks the file as ours), of each object's material ("material":
// the scene's material as scene v1 writes it, or "default_material": true) and of each light's
// material ("radiance"). Conversions between JSON and tinygltf's values. Free functions;
// thread-safe.
#pragma once

#include <tiny_gltf.h>

#include <nlohmann/json.hpp>

namespace penumbra::interchange {

inline constexpr const char* kPenumbraExtras = "penumbra";
// The vertex attribute that names each vertex's scene face (its index within its object, as a
// float; every vertex belongs to one face): the importer rebuilds each face from its triangles.
inline constexpr const char* kFaceAttribute = "_FACE";

tinygltf::Value toGltfValue(const nlohmann::json& json);
nlohmann::json toJson(const tinygltf::Value& value);

// extras.penumbra of an object (material, asset, …) as JSON; null when it has none.
nlohmann::json penumbraExtras(const tinygltf::Value& extras);

}  // namespace penumbra::interchange
