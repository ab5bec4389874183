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

// Frames whose work grows with the whole scene rather than with what they move: a light added or
// reshaped (every receiver is cast again; a frame adding 22 lights took 20 s), a volume added or
// changed, an object of more than kHeavyObjectFaces faces added. EditWorkers runs them on its
// heavy lane (one thread, lower priority), so that other scenes' drags never wait behind them.
inline constexpr size_t kHeavyObjectFaces = 1000;
bool isHeavyFrame(const Frame& frame);

}  // namespace penumbra::server
