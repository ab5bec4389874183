// Mesh JSON v1 (SCENE_FORMAT.md "Exported mesh") <-> penumbra::Mesh: an exact
// writer and a validating reader (for tests and tools). Free functions; thread-safe.
#pragma once

#include <functional>
#include <iosfwd>
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

// The text of meshToJson(...).dump() (compact, invalid UTF-8 in names replaced) and a newline,
// streamed: the mesh is never a JSON document in memory (it was ~430 MB of `penumbra build`'s
// peak on sparse 1,500 cubes).
void writeMeshJson(std::ostream& out, const Scene& scene, const Mesh& mesh, const std::string& sceneName);

// Members a writer adds to that document: `root`'s members to the top level, receiver(k)'s (an
// object, or null) to receiver k. Each is merged in key order and replaces a member of the same
// name, so the text is that of the document with the members set by operator[] (the server's
// ids, versions, deltas and indirect light; docs/API.md).
// valuesOnly(k) true: receiver k is written with "object", "face" and "irradiance" alone (and
// its extras), for a reader that holds its shape already (the server's values-only deltas).
struct MeshJsonExtras {
  nlohmann::json root = nlohmann::json::object();
  std::function<nlohmann::json(size_t receiver)> receiver;  // empty: none
  std::function<bool(size_t receiver)> valuesOnly;          // empty: every receiver whole
};
void writeMeshJson(std::ostream& out, const Scene& scene, const Mesh& mesh, const std::string& sceneName,
                   const MeshJsonExtras& extras);

// What a mesh file states besides the receivers: "tolerance" (the interpolation bound the
// display mesh was refined to, relative to each light's local unshadowed level; 0: not refined)
// and "capped_cells" (cells whose refinement stopped at the point cap short of it).
// meshFromJson reads them back when present.
nlohmann::json meshFileRoot(const Mesh& mesh);

// Files are written compactly by writeMeshJson with meshFileRoot's members; reading uses the
// limits of protocol/json_text.h.
void saveMeshFile(const Scene& scene, const Mesh& mesh, const std::string& sceneName,
                  const std::string& path);
Mesh loadMeshFile(const std::string& path, const Scene& scene);

}  // namespace penumbra::protocol
