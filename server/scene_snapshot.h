// One whole version of a served scene: scene, lit mesh in parts, and per part the version of
// its last change. Immutable once published; shared read-only by any number of threads.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/engine/build_stats.h"
#include "core/engine/frame.h"
#include "core/mesh/mesh.h"
#include "core/scene/scene.h"
#include "protocol/mesh_json.h"
#include "server/scene_occluders.h"

namespace penumbra::server {

// A receiver as clients name it: the object's id and the face's index in it.
struct ReceiverKey {
  std::string object;
  uint32_t face = 0;
  auto operator<=>(const ReceiverKey&) const = default;
};

// A display chunk of a receiver's mesh as clients name it (Engine::MeshChunkKey).
struct PartKey {
  ReceiverKey receiver;
  int64_t x = 0, y = 0;
  auto operator<=>(const PartKey&) const = default;
};

// One part of the lit mesh: a receiver's chunk, shared read-only between versions
// while it does not change.
struct MeshPart {
  PartKey key;
  std::shared_ptr<const ReceiverMesh> mesh;
  uint64_t version = 0;  // the scene version of its last change
  // The scene version of its last change of shape (positions, triangles, normal or classes):
  // at most `version`; below it when only the irradiance changed since (a light's radiance).
  uint64_t shapeVersion = 0;
};

// What a mesh response carries: parts (the binary form) and, for mesh JSON, whole
// receivers. Indices are into SceneSnapshot::parts, ascending.
struct MeshSelection {
  std::optional<uint64_t> since;        // empty: the whole mesh
  std::vector<size_t> parts;            // changed in shape after `since`: sent whole
  std::vector<size_t> valueParts;       // changed after `since` in their irradiance alone
  std::vector<PartKey> removedParts;    // gone after `since`
  std::vector<ReceiverKey> receivers;   // receivers with a changed part (scene order)
  // Of `receivers`, those whose every change after `since` is a part's irradiance (no part
  // changed in shape, added or removed): mesh JSON sends them as values only (scene order).
  std::vector<ReceiverKey> valueReceivers;
  std::vector<ReceiverKey> removed;     // receivers gone after `since` (no part left)
};

// The "version" of a served mesh JSON delta: mesh JSON v1 whose receivers may be values only.
inline constexpr int kMeshDeltaJsonVersion = 2;

struct SceneSnapshot {
  std::string id;
  std::string name;  // the scene file's name, or the name given at creation
  uint64_t version = 0;
  Scene scene;
  // The lit mesh in parts: receivers in Scene::faces() order, each its chunks in key order.
  std::vector<MeshPart> parts;
  // Parts that have left (a receiver left the scene, or a chunk became empty), with the
  // version that removed them: every part removed after removedFloor (older ones are
  // forgotten, so the list stays bounded; a `since` older than the floor gets the whole mesh).
  std::vector<std::pair<PartKey, uint64_t>> removed;
  uint64_t removedFloor = 0;
  // Per microfacet receiver its DM cells' occluder lists, frozen at this version: images shade
  // microfacet surfaces with the DM's exact visibility without touching the engine.
  std::shared_ptr<const OccluderIndexes> occluders = std::make_shared<const OccluderIndexes>();
  BuildStats buildStats;                 // of the initial build
  std::optional<FrameResult> lastFrame;  // the frame that made this version
  // The version whose fresh build the engine that applied that frame came from (its base:
  // creation, a rebuilding light edit, a snapshot's rebase). Journaled with the frame, so a
  // restart builds afresh where the server did (scene_session.h, rebase()).
  uint64_t frameBase = 0;

  // Everything (since empty) or only what changed after `since`; the whole mesh too when
  // `since` is older than removedFloor (the selection's `since` is then empty).
  MeshSelection select(std::optional<uint64_t> since) const;
  // Forgets removed parts at or before `floor` (docs/API.md "Deltas and old versions").
  void forgetRemovedUpTo(uint64_t floor);

  // The whole lit mesh, each receiver its parts concatenated (as Engine::mesh()); made
  // on first use (thread-safe), for mesh JSON, GLB and images.
  const Mesh& mesh() const;
  size_t receiverCount() const;
  size_t vertexCount() const;
  size_t triangleCount() const;

  // Writes mesh JSON v1 (SCENE_FORMAT.md) of the selection's receivers, plus "id",
  // "scene_version", "since", per receiver "scene_version", "removed" (docs/API.md) and
  // `more`'s members; streamed, never a JSON document (it was ~10× the text's size). A delta
  // (`since` set) says "version": 2 and writes its valueReceivers with their irradiance alone.
  void writeMeshJson(std::ostream& out, const MeshSelection& selection,
                     const protocol::MeshJsonExtras& more = {}) const;

 private:
  mutable std::once_flag meshOnce_;
  mutable Mesh mesh_;
};

nlohmann::json toJson(const ReceiverKey& key);
nlohmann::json toJson(const PartKey& key);

}  // namespace penumbra::server
