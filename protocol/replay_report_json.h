// The report of `penumbra replay --report` (format "penumbra.replay-report", version 1): what
// each replayed frame cost and, with --verify, how it compared with a full rebuild, and the
// totals over the script. Plain values filled by the CLI; free functions; thread-safe.
#pragma once

#include <cmath>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/engine/frame.h"

namespace penumbra::protocol {

// One frame as replayed: Engine::apply's result and what the replay timed around it.
struct ReplayFrame {
  size_t line = 0;             // the frame's line in the edit script
  FrameResult result;
  double wallSeconds = 0;      // Engine::apply, wall clock
  double meshSeconds = NAN;    // --display-mesh: Engine::mesh() after the frame
  bool verified = false;       // --verify checked this frame against a full rebuild
  double rebuildSeconds = NAN; // verified frames: that rebuild's time
};

// Sums over the frames (the verified ones only where named so).
struct ReplayTotals {
  FrameTimings seconds;
  size_t relit = 0, changed = 0, created = 0, rebuilds = 0, fullRebuilds = 0, verified = 0;
  double rebuildSeconds = 0, editSecondsVerified = 0, meshSeconds = 0;
};

struct ReplayReport {
  std::string scene, script;  // the paths as given
  double buildSeconds = 0;    // the initial build
  bool displayMesh = false;   // frames carry meshSeconds
  std::vector<ReplayFrame> frames;
  std::optional<std::string> verifyFailure;  // the first frame that differed from its rebuild
};

ReplayTotals replayTotals(const ReplayReport& report);

// {"format", "version", "scene", "script", "build_seconds", "frames": [frame result counters
// (frameResultCountsToJson) with "frame", "line", "wall_seconds", "full_rebuild", "verified",
// and "mesh_seconds", "rebuild_seconds", "edit_over_rebuild" where measured], "totals",
// "verify_failure"}.
nlohmann::json replayReportToJson(const ReplayReport& report);

}  // namespace penumbra::protocol
