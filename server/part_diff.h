// What a frame did to a scene's mesh parts, between the version before it and the one it makes:
// which parts came (new, or back after leaving), which left, and whose versions moved (in shape,
// or in irradiance alone). SceneSession::applyToEngine diffs the parts it meshed again;
// replayJournaled applies the diff a frame journaled (PartChanges). Free functions on snapshot
// data; no shared state.
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include "server/scene_snapshot.h"

namespace penumbra::server {

// Gives each part meshed again its versions from the part it replaces in `before` (the previous
// version's parts of the receivers meshed again or gone, by key): the same mesh keeps both
// versions, the same shape keeps its shape version, anything else (and a part new to `before`)
// keeps the frame's version it was made with. Returns the keys of `before` that were not meshed
// again, in key order: the parts that left.
std::vector<PartKey> carryPartVersions(std::map<PartKey, const MeshPart*> before,
                                       const std::vector<MeshPart*>& fresh);

// The removals after a frame at `version`, in place on `next.removed` (SceneSnapshot::removed):
// a part `live` again after leaving drops its removal, the parts that `left` are appended at
// `version`, and removals older than the since window (kSinceWindow) are forgotten.
void recordRemovals(SceneSnapshot& next, const std::set<PartKey>& live,
                    const std::vector<PartKey>& left, uint64_t version);

}  // namespace penumbra::server
