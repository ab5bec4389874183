// One whole version of a served scene: scene, lit mesh, and per receiver the version of its
// last change. Immutable once published; shared read-only by any number of threads.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/engine/build_stats.h"
#include "core/engine/frame.h"
#include "core/mesh/mesh.h"
#include "core/scene/scene.h"

namespace penumbra::server {

// A receiver as clients name it: the object's id and the face's index in it.
struct ReceiverKey {
  std::string object;
  uint32_t face = 0;
  auto operator<=>(const ReceiverKey&) const = default;
};

// Which receivers a mesh response carries (indices into SceneSnapshot::mesh.receivers,
// ascending) and which receivers left the scene since the asked version.
struct MeshSelection {
  std::optional<uint64_t> since;  // empty: the whole mesh
  std::vector<size_t> receivers;
  std::vector<ReceiverKey> removed;
};

struct SceneSnapshot {
  std::string id;
  std::string name;  // the scene file's name, or the name given at creation
  uint64_t version = 0;
  Scene scene;
  Mesh mesh;
  std::vector<ReceiverKey> receiverKeys;   // parallel to mesh.receivers
  std::vector<uint64_t> receiverVersions;  // parallel: version of the last change
  // Receivers that have left the scene, with the version that removed them.
  std::vector<std::pair<ReceiverKey, uint64_t>> removed;
  BuildStats buildStats;                 // of the initial build
  std::optional<FrameResult> lastFrame;  // the frame that made this version

  // Everything (since empty) or only what changed after `since`.
  MeshSelection select(std::optional<uint64_t> since) const;

  // Mesh JSON v1 (SCENE_FORMAT.md) of the selection, plus "id", "scene_version",
  // "since", per receiver "scene_version", and "removed" (docs/API.md).
  nlohmann::json meshJson(const MeshSelection& selection) const;
};

nlohmann::json toJson(const ReceiverKey& key);

}  // namespace penumbra::server
