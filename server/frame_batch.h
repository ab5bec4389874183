// Coalescing of queued edit frames (docs/API.md "Load"): frames of different clients that
// touch different objects are applied as one frame — one engine pass, one meshing, one journal
// commit, one version. Free function; thread-safe.
#pragma once

#include <optional>
#include <vector>

#include "core/engine/frame.h"

namespace penumbra::server {

// The frames' edits in order as one frame, or nullopt when two of the frames name the same
// object id (their order would matter: they are applied one by one instead).
std::optional<Frame> combinedFrame(const std::vector<const Frame*>& frames);

}  // namespace penumbra::server
