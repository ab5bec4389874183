// What Engine::apply did to one frame (core FrameResult) as JSON: version, seconds
// split into remove/add/relight, vertex counters, receivers by {object id, face}.
// Free function; thread-safe.
#pragma once

#include <nlohmann/json.hpp>

#include "core/engine/frame.h"
#include "core/scene/scene.h"

namespace penumbra::protocol {

// `scene` is the scene after the frame: changed receivers are named by their
// object's id there. Removed receivers whose object left the scene are named by
// handle ({"handle": h, "face": f}), the others by id. Also gives counts.
nlohmann::json frameResultToJson(const FrameResult& result, const Scene& scene);
// The same without the receiver lists ("changed_receivers", "removed_receivers"): the counters
// only, as the replay report keeps per frame.
nlohmann::json frameResultCountsToJson(const FrameResult& result);

}  // namespace penumbra::protocol
