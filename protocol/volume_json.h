// Volume objects in scene JSON (SCENE_FORMAT.md "Volume objects"): {"id", "type": "volume",
// "file", "isovalue", "material", "transform"}, the NRRD read through protocol/nrrd_volume.
// Free functions; thread-safe.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/scene/scene.h"
#include "protocol/nrrd_volume.h"

namespace penumbra::protocol {

// Where a scene's volume files come from. Without one (a scene posted over HTTP, a fuzzer's
// text) volume objects are refused: such a scene must not make the reader open files.
struct VolumeFiles {
  std::string baseDirectory;  // relative `file` paths resolve against it (the scene's folder)
  NrrdLimits limits;
  // A client's frame (POST .../edits) may name only files the server already holds: its own
  // uploads (under knownDirectory) and the files of the scene's volumes as it was loaded.
  bool onlyKnown = false;
  std::string knownDirectory;
  std::vector<std::string> knownFiles;  // resolved paths
};

// Whether an objects[] entry is a volume ("type": "volume"); throws ValidationError at
// `path.type` for any other type (polygon objects have no "type").
bool isVolumeObject(const nlohmann::json& value, const std::string& path);

// Validates one volume object at `path` (all checks but id uniqueness) and reads its file;
// every problem of the file is a ValidationError at `path.file`.
VolumeObject volumeFromJson(const nlohmann::json& value, const std::string& path,
                            const std::vector<Material>& materials, const VolumeFiles* files);
// `file` is written as resolved (absolute), so the JSON reads back from anywhere.
nlohmann::json volumeToJson(const VolumeObject& volume);

}  // namespace penumbra::protocol
