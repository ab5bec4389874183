// Mesh JSON v1 (SCENE_FORMAT.md "Exported mesh") <-> penumbra::Mesh: an exact
// writer and a validating reader (for tests and tools). Free functions; thread-safe.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "core/mesh/mesh.h"
#include "core/scene/scene.h"
#include "protocol/validation_error.h"

namespace penumbra::protocol {

// sceneName goes into "scene" (usually the scene file's name). Receivers name
// their object by id. Throws std::out_of_range if a receiver's face is not in
// the scene (a programming error, not bad input).
nlohmann::json meshToJson(const Scene& scene, const Mesh& mesh, const std::string& sceneName);

// Validates against the scene (object ids, face indices, array lengths,
// triangle indices, class names) and throws ValidationError with the key path of
// the first problem.
Mesh meshFromJson(const nlohmann::json& root, const Scene& scene);

// Files are written compactly (meshes are large); reading uses the limits of
// protocol/json_text.h.
void saveMeshFile(const Scene& scene, const Mesh& mesh, const std::string& sceneName,
                  const std::string& path);
Mesh loadMeshFile(const std::string& path, const Scene& scene);

}  // namespace penumbra::protocol
