// BuildStats (core) as JSON: the one schema of a full build's counters and step times, used by
// the server (/stats "build", rebuild reports), `penumbra build --stats` and the build bench.
// Free function; thread-safe.
#pragma once

#include <nlohmann/json.hpp>

#include "core/engine/build_stats.h"

namespace penumbra::protocol {

// {"faces", "receivers", "lights", "candidate_pairs", "closed_convex_pairs", "cast_attempts",
//  "pairs_with_shadow", "tiles", "order_fragments", "tree_nodes", "cells",
//  "vertices": {"total", "lit", "penumbra", "umbra"}, "comparisons_per_vertex",
//  "seconds": {"ordering", "cube", "casting_and_merging", "illumination", "triangulation", "total"}}.
nlohmann::json buildStatsToJson(const BuildStats& stats);

}  // namespace penumbra::protocol
