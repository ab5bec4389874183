// JSON bodies of the server's answers built from engine and session values: rebuild reports
// (build statistics: protocol/build_stats_json.h), scene summaries, and which receivers a version changed. Pure; thread-safe.
#pragma once

#include <cstdint>

#include <nlohmann/json.hpp>

#include "core/engine/build_stats.h"
#include "server/scene_session.h"
#include "server/scene_snapshot.h"

namespace penumbra::server {

nlohmann::json rebuildJson(const RebuildReport& r);
// {"id", "name", "version", "objects", "faces", "receivers", "url"}.
nlohmann::json sceneSummaryJson(const SceneSnapshot& s);
// Receivers whose mesh changed after version `after`, and those that left the scene since:
// {"version", "changed", "removed"}.
nlohmann::json changedAtJson(const SceneSnapshot& s, uint64_t after);
// What a page needs to draw and edit a volume beside its scene JSON: {"id", "voxel_type",
// "size": [nx, ny, nz], "value_range": [min, max], "axes": the grid box's three edges in
// object space (objectFromVoxel's columns × (size − 1)), "isovalue"}.
nlohmann::json volumeInfoJson(const VolumeObject& volume);
// volumeInfoJson of every volume of the scene, in order.
nlohmann::json volumesInfoJson(const Scene& scene);

}  // namespace penumbra::server
