#include "protocol/replay_report_json.h"

#include "protocol/frame_result_json.h"

namespace penumbra::protocol {

namespace {

using nlohmann::json;

json frameJson(const ReplayFrame& f, size_t number, bool displayMesh) {
  json entry = frameResultCountsToJson(f.result);
  entry["frame"] = number;
  entry["line"] = f.line;
  entry["wall_seconds"] = f.wallSeconds;
  entry["full_rebuild"] = f.result.fullRebuild;  // a large frame: the engine was rebuilt
  if (displayMesh) entry["mesh_seconds"] = f.meshSeconds;
  entry["verified"] = f.verified;
  if (f.verified) {
    entry["rebuild_seconds"] = f.rebuildSeconds;
    entry["edit_over_rebuild"] = f.result.seconds.total() / f.rebuildSeconds;
  }
  return entry;
}

json totalsJson(const ReplayTotals& t, size_t frames, bool displayMesh) {
  return {{"frames", frames},
          {"seconds",
           {{"remove", t.seconds.remove},
            {"add", t.seconds.add},
            {"relight", t.seconds.relight},
            {"total", t.seconds.total()}}},
          {"vertices", {{"relit", t.relit}, {"changed", t.changed}, {"created", t.created}}},
          {"mesh_seconds", displayMesh ? json(t.meshSeconds) : json(nullptr)},
          {"tree_rebuilds", t.rebuilds},
          {"full_rebuild_frames", t.fullRebuilds},
          {"verified_frames", t.verified},
          {"rebuild_seconds_verified", t.rebuildSeconds},
          {"edit_seconds_verified", t.editSecondsVerified},
          {"edit_over_rebuild",
           t.rebuildSeconds > 0 ? json(t.editSecondsVerified / t.rebuildSeconds) : json(nullptr)}};
}

}  // namespace

ReplayTotals replayTotals(const ReplayReport& report) {
  ReplayTotals t;
  for (const ReplayFrame& f : report.frames) {
    const FrameResult& r = f.result;
    if (report.displayMesh) t.meshSeconds += f.meshSeconds;
    t.seconds.remove += r.seconds.remove;
    t.seconds.add += r.seconds.add;
    t.seconds.relight += r.seconds.relight;
    t.relit += r.verticesRelit;
    t.changed += r.verticesChanged;
    t.created += r.verticesCreated;
    t.rebuilds += r.treeRebuilds;
    t.fullRebuilds += r.fullRebuild ? 1 : 0;
    if (!f.verified) continue;
    ++t.verified;
    t.rebuildSeconds += f.rebuildSeconds;
    t.editSecondsVerified += r.seconds.total();
  }
  return t;
}

json replayReportToJson(const ReplayReport& report) {
  json frames = json::array();
  for (size_t i = 0; i < report.frames.size(); ++i)
    frames.push_back(frameJson(report.frames[i], i + 1, report.displayMesh));
  return {{"format", "penumbra.replay-report"},
          {"version", 1},
          {"scene", report.scene},
          {"script", report.script},
          {"build_seconds", report.buildSeconds},
          {"frames", std::move(frames)},
          {"totals", totalsJson(replayTotals(report), report.frames.size(), report.displayMesh)},
          {"verify_failure", report.verifyFailure ? json(*report.verifyFailure) : json(nullptr)}};
}

}  // namespace penumbra::protocol
