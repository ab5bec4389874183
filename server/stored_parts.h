// A served version's mesh parts as a journal snapshot keeps them (scene_journal.h): every part's
// key, version and mesh bit for bit, and the removed parts `since` deltas still name. Free
// functions; thread-safe.
#pragma once

#include <string>

#include "server/scene_snapshot.h"

namespace penumbra::server {

// What a snapshot restores besides the scene JSON: SceneSnapshot's parts, removed and
// removedFloor, and the scene's object handles (JSON holds none; the parts' meshes name them).
struct StoredParts {
  std::vector<MeshPart> parts;
  std::vector<std::pair<PartKey, uint64_t>> removed;
  uint64_t removedFloor = 0;
  std::vector<uint32_t> handles;  // Scene::handleOf of each object
  uint32_t nextHandle = 0;
};

// Little-endian bytes of the raw values (doubles as their bits: the restored mesh is the served
// one byte for byte).
std::string encodeStoredParts(const SceneSnapshot& snapshot);
// Throws std::runtime_error when `bytes` is not what encodeStoredParts wrote.
StoredParts decodeStoredParts(const std::string& bytes);

}  // namespace penumbra::server
