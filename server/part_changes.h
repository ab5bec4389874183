// What one applied frame did to a scene's served mesh (README "Durability"): the parts whose
// version it moved and the parts it removed. Journaled beside the frame, so that a restart can
// replay the frames through the engine alone and mesh once at the end
// (SceneSession::replayJournaled) instead of meshing after every frame.
#pragma once

#include <string>
#include <vector>

#include "server/scene_snapshot.h"

namespace penumbra::server {

struct PartChanges {
  std::vector<PartKey> changed;  // parts at the frame's version in shape (new, or reshaped)
  std::vector<PartKey> removed;  // parts that left at the frame's version, in snapshot order
  std::vector<PartKey> values;   // parts whose irradiance alone changed at the frame's version
};

// Read off the version a frame made: parts and removals at `next.version`.
PartChanges partChangesOf(const SceneSnapshot& next);

// Compact JSON: {"changed": [[object, face, x, y], …], "removed": […], "values": […]}; text
// without "values" (journaled before values-only parts) reads as none.
std::string partChangesText(const PartChanges& changes);
// Throws std::runtime_error on text partChangesText did not write.
PartChanges partChangesFromText(const std::string& text);

}  // namespace penumbra::server
