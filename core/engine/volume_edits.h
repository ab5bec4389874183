// Volume edits of a frame (SCENE_FORMAT.md "Volume objects"): a move or remove naming a
// volume, set_volume (a new isovalue) and add_volume. They change Scene::volumes() only:
// the DM never sees volumes, so the engine does no shadow work for them.
// VolumeEditCheck: one per frame check, not shared; the free functions are thread-safe.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "core/engine/frame.h"
#include "core/scene/scene.h"

namespace penumbra {

// Why `isovalue` cannot be a volume's with this data: not finite, or outside the data's
// value range [minValue, maxValue] (no surface there); nullopt if it can.
std::optional<std::string> isovalueProblem(const volume::ScalarVolume& data, double isovalue);

// The volumes as a frame's earlier edits leave them; checks each volume edit in order.
class VolumeEditCheck {
 public:
  explicit VolumeEditCheck(const Scene& scene);
  // Whether `id` names a volume now (as the checked edits leave them).
  bool has(const std::string& id) const { return volumes_.count(id) > 0; }
  // Whether the edit is a volume's: set_volume, add_volume, or a move / remove naming a
  // volume (now).
  bool concerns(const Edit& edit) const;
  // Checks edit `index` (one concerns() holds for) and notes its effect. `objectExists` says
  // whether a polygon object has an id (as the frame's earlier edits leave them). Throws
  // EditError: "id" (unknown volume), "isovalue" (isovalueProblem), "transform" (not finite,
  // zero scale), "volume.id" (taken), "volume" (no data), "volume.material" (unknown),
  // "volume.isovalue".
  void check(const Edit& edit, size_t index,
             const std::function<bool(const std::string&)>& objectExists);

 private:
  const Scene& scene_;
  std::map<std::string, std::shared_ptr<const volume::ScalarVolume>> volumes_;
};

// Applies a checked volume edit to the scene (Scene::addVolume / removeVolume /
// setVolumeTransform / setVolumeIsovalue).
void applyVolumeEdit(Scene& scene, const Edit& edit);

}  // namespace penumbra
