// A create-scene request that imports a file (POST /api/scenes?format=obj|gltf|glb): its bytes,
// MTL files and import options, read from the request (docs/API.md). Free functions; thread-safe.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "interchange/imported_geometry.h"

namespace httplib {
struct Request;
}

namespace penumbra::server {

struct SceneUpload {
  std::vector<uint8_t> bytes;  // the OBJ text, glTF JSON or GLB
  std::string fileName;        // its extension picks the reader (importSceneBytes)
  std::map<std::string, std::string>
      mtlFiles;                        // OBJ only: MTL texts by the names its 'mtllib' lines use
  interchange::ImportOptions options;  // query scale, light_radiance, studio
};

// nullopt: the request carries scene JSON (no `format`, or `format=scene`, and not a form).
// Otherwise the upload: the raw body, or a multipart form with one part "file" and any number
// of parts "mtl". Throws ApiError 400 naming `query.<name>` or `(form).<part>` when the query
// or the form is malformed (nothing is imported then).
std::optional<SceneUpload> sceneUploadOf(const httplib::Request& req);

}  // namespace penumbra::server
