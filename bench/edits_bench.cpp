// `penumbra-bench edits`: edit scripts (bench/lib/edit_scripts) applied frame by
// frame with Engine::apply on generated 'N cubes in a room' scenes (with the
// subject cube, so the drag moves the same cube at every N), against a full
// rebuild of the same scene (an Engine built from scratch, timed in the same run)
// on every frame or every K-th; JSON and a self-contained HTML report. --dense: the dense
// rooms, one floating box dragged (bench/lib/dense_drag.h; issue 11's move-one-box ratio).
// With --write-scripts DIR --scene FILE it only writes that scene's standard scripts as
// .edits.jsonl.
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <vector>

#include "bench/bench_args.h"
#include "bench/lib/dense_drag.h"
#include "bench/lib/edit_scripts.h"
#include "bench/report/edits_report_html.h"
#include "core/engine/engine.h"
#include "core/engine/seconds_since.h"
#include "protocol/edits_json.h"
#include "protocol/json_text.h"
#include "protocol/scene_json.h"
#include "scenegen/cubes_scene.h"
#include "scenegen/dense_scene.h"

namespace penumbra::bench {

namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

// The middle value (the mean of the two middle ones for an even count); 0 if empty.
double median(std::vector<double> values) {
  if (values.empty()) return 0;
  const size_t half = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + half, values.end());
  if (values.size() % 2) return values[half];
  return 0.5 * (values[half] + *std::max_element(values.begin(), values.begin() + half));
}

json ratioOrNull(double a, double b) { return b > 0 ? json(a / b) : json(nullptr); }

// Frames per script by scene size: every frame costs a full rebuild (and, until
// the incremental apply lands, a second one inside apply).
// Large moved shares cost minutes per frame at N = 1500 (2026-11: 30% took 5 min),
// so only small scenes run them by default.
struct Budget {
  int drag, shareFrames;
  double maxShare;
  int removeAddPairs, buildUp;
};
// Dense rooms run the drag only, and build slower than sparse ones at the same N.
Budget budgetFor(int cubes, const BenchArgs& args) {
  Budget b = args.dense      ? Budget{cubes <= 300 ? 20 : 10, 0, 0, 0, 0}
             : cubes <= 200  ? Budget{100, 5, 0.30, 5, 40}
             : cubes <= 2000 ? Budget{5, 1, 0.01, 0, 0}
                             : Budget{2, 0, 0, 0, 0};
  if (args.frames > 0) b.drag = args.frames;
  return b;
}

// Frames between timed full rebuilds: every frame up to 2000 cubes; beyond, a
// rebuild costs ~30 s (5000 cubes, 2026-11), so every 10th. Dense rooms: every frame up
// to 300 boxes, else every 5th (a dense rebuild at 1500 is the 120 s budget).
int rebuildEveryFor(int cubes, const BenchArgs& args) {
  if (args.rebuildEvery > 0) return args.rebuildEvery;
  if (args.dense) return cubes <= 300 ? 1 : 5;
  return cubes <= 2000 ? 1 : 10;
}

json frameJson(size_t frame, const FrameResult& result, double wall, const json& rebuildSeconds,
               const json& editOverRebuild) {
  return {{"frame", frame},
          {"seconds",
           {{"remove", result.seconds.remove},
            {"add", result.seconds.add},
            {"relight", result.seconds.relight},
            {"total", result.seconds.total()}}},
          {"wall_seconds", wall},
          {"rebuild_seconds", rebuildSeconds},
          {"edit_over_rebuild", editOverRebuild},
          {"vertices",
           {{"relit", result.verticesRelit},
            {"changed", result.verticesChanged},
            {"created", result.verticesCreated}}},
          {"changed_receivers", result.changedReceivers.size()},
          {"tree_rebuilds", result.treeRebuilds},
          {"full_rebuild", result.fullRebuild},
          {"nodes_deleted", result.nodesDeleted}};
}

// Runs the script on the engine, timing a full rebuild after the first frame,
// every `rebuildEvery`-th and the last (other frames: rebuild_seconds null).
json runScript(Engine& engine, const EditScript& script, int rebuildEvery) {
  json frames = json::array();
  double edit = 0, rebuild = 0, relit = 0, changed = 0, treeRebuilds = 0;
  std::vector<double> edits, walls, rebuilds;
  size_t fullRebuilds = 0;
  for (size_t i = 0; i < script.frames.size(); ++i) {
    const auto wallStart = Clock::now();
    const FrameResult result = engine.apply(script.frames[i]);
    const double wall = secondsSince(wallStart);
    json rebuildSeconds = nullptr, editOverRebuild = nullptr;
    if (i % size_t(rebuildEvery) == 0 || i + 1 == script.frames.size()) {
      const auto rebuildStart = Clock::now();
      { const Engine rebuilt(engine.scene(), engine.settings()); }
      const double seconds = secondsSince(rebuildStart);
      rebuildSeconds = seconds;
      editOverRebuild = result.seconds.total() / seconds;
      rebuild += seconds;
      rebuilds.push_back(seconds);
    }
    edit += result.seconds.total();
    relit += double(result.verticesRelit);
    changed += double(result.verticesChanged);
    treeRebuilds += double(result.treeRebuilds);
    edits.push_back(result.seconds.total());
    walls.push_back(wall);
    fullRebuilds += result.fullRebuild ? 1 : 0;
    frames.push_back(frameJson(i + 1, result, wall, rebuildSeconds, editOverRebuild));
  }
  const double n = std::max<double>(1, double(script.frames.size()));
  const double timed = std::max<double>(1, double(rebuilds.size()));
  const double meanEdit = edit / n, meanRebuild = rebuild / timed;
  const double first = edits.empty() ? 0 : edits.front();
  const double medianEdit = median(edits), medianRebuild = median(rebuilds);
  std::printf(
      "  %-12s %4zu frames  %6zu faces (%5.1f%%)  edit %9.2f ms  rebuild %9.2f ms  ratio %6.3f  "
      "relit %9.0f  changed %9.0f\n"
      "  %-12s first %9.2f ms  median %9.2f ms  median rebuild %9.2f ms (%zu timed)  full rebuilds "
      "%zu%s%s\n",
      script.name.c_str(), script.frames.size(), script.editedFaces, 100 * script.faceShare,
      1e3 * meanEdit, 1e3 * meanRebuild, meanRebuild > 0 ? meanEdit / meanRebuild : 0.0, relit / n,
      changed / n, "", 1e3 * first, 1e3 * medianEdit, 1e3 * medianRebuild, rebuilds.size(),
      fullRebuilds, script.subject.empty() ? "" : "  ", script.subject.c_str());
  if (medianRebuild > 0)
    std::printf("  %-12s over the median rebuild: first %.4f  median %.4f  mean %.4f\n", "",
                first / medianRebuild, medianEdit / medianRebuild, meanEdit / medianRebuild);
  std::fflush(stdout);
  return {{"name", script.name},
          {"subject", script.subject},
          {"first_edit_seconds", first},
          {"median_edit_seconds", medianEdit},
          {"median_wall_seconds", median(walls)},
          {"median_rebuild_seconds", medianRebuild},
          // Issue 11's move-one-box measure: the edit against the median timed rebuild.
          {"first_over_rebuild", ratioOrNull(first, medianRebuild)},
          {"median_over_rebuild", ratioOrNull(medianEdit, medianRebuild)},
          {"mean_over_rebuild", ratioOrNull(meanEdit, medianRebuild)},
          {"rebuild_frames", rebuilds.size()},
          {"full_rebuild_frames", fullRebuilds},
          {"edited_faces", script.editedFaces},
          {"face_share", script.faceShare},
          {"mean_edit_seconds", meanEdit},
          {"mean_rebuild_seconds", meanRebuild},
          {"edit_over_rebuild", meanRebuild > 0 ? meanEdit / meanRebuild : 0.0},
          {"mean_relit", relit / n},
          {"mean_changed", changed / n},
          {"mean_tree_rebuilds", treeRebuilds / n},
          {"frames", std::move(frames)}};
}

json writeScripts(const BenchArgs& args) {
  if (args.scenePath.empty()) throw std::invalid_argument("--write-scripts needs --scene FILE");
  const Scene scene = protocol::loadSceneFile(args.scenePath);
  std::string stem = std::filesystem::path(args.scenePath).filename().string();
  stem = stem.substr(0, stem.find('.'));
  json written = json::array();
  for (const EditScript& script : standardEditScripts(scene, args.seed)) {
    const std::string path =
        (std::filesystem::path(args.writeScripts) / (stem + "." + script.name + ".edits.jsonl"))
            .string();
    protocol::writeTextFile(path, protocol::writeEditScript(script.frames));
    std::printf("wrote %s: %zu frames, %zu faces edited (%.1f%%)\n", path.c_str(),
                script.frames.size(), script.editedFaces, 100 * script.faceShare);
    written.push_back(
        {{"path", path}, {"frames", script.frames.size()}, {"face_share", script.faceShare}});
  }
  return {{"benchmark", "edits"}, {"written", written}};
}

// Issue 4's measure: the drag's edit time per scene size (first frame, median,
// mean) and the median of the largest N over the median of the smallest.
json dragVsSize(const json& scenes) {
  json sizes = json::array();
  for (const json& scene : scenes)
    for (const json& script : scene["scripts"])
      if (script["name"] == "drag")
        sizes.push_back({{"cubes", scene["cubes"]},
                         {"subject", script["subject"]},
                         {"frames", script["frames"].size()},
                         {"first_edit_seconds", script["first_edit_seconds"]},
                         {"median_edit_seconds", script["median_edit_seconds"]},
                         {"median_wall_seconds", script["median_wall_seconds"]},
                         {"mean_edit_seconds", script["mean_edit_seconds"]},
                         {"median_rebuild_seconds", script["median_rebuild_seconds"]},
                         {"first_over_rebuild", script["first_over_rebuild"]},
                         {"median_over_rebuild", script["median_over_rebuild"]},
                         {"mean_over_rebuild", script["mean_over_rebuild"]},
                         {"rebuild_frames", script["rebuild_frames"]}});
  json out = {{"sizes", sizes}, {"median_ratio", nullptr}};
  if (sizes.size() >= 2) {
    const auto [smallest, largest] = std::minmax_element(
        sizes.begin(), sizes.end(),
        [](const json& a, const json& b) { return a["cubes"].get<int>() < b["cubes"].get<int>(); });
    const double from = (*smallest)["median_edit_seconds"].get<double>();
    const double to = (*largest)["median_edit_seconds"].get<double>();
    const double wallFrom = (*smallest)["median_wall_seconds"].get<double>();
    const double wallTo = (*largest)["median_wall_seconds"].get<double>();
    out["median_ratio"] = {{"from_cubes", (*smallest)["cubes"]},
                           {"to_cubes", (*largest)["cubes"]},
                           {"ratio", from > 0 ? json(to / from) : json(nullptr)},
                           {"wall_ratio", wallFrom > 0 ? json(wallTo / wallFrom) : json(nullptr)}};
    std::printf(
        "drag median edit time, N = %d → %d: %.2f ms → %.2f ms, ratio %.2f (wall, with the "
        "frame check: %.2f ms → %.2f ms, ratio %.2f)\n",
        (*smallest)["cubes"].get<int>(), (*largest)["cubes"].get<int>(), 1e3 * from, 1e3 * to,
        from > 0 ? to / from : 0.0, 1e3 * wallFrom, 1e3 * wallTo,
        wallFrom > 0 ? wallTo / wallFrom : 0.0);
  }
  return out;
}

}  // namespace

json runEditsBench(const BenchArgs& args) {
  if (!args.writeScripts.empty()) return writeScripts(args);
  const tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
  const std::vector<int> sizes = args.cubesGiven ? args.cubes : std::vector<int>{150, 1500, 5000};
  json scenes = json::array();
  for (int cubes : sizes) {
    CubesSceneOptions options;
    options.cubes = cubes;
    options.seed = args.seed;
    options.lightScale = args.lightScale;
    options.subjectCube = true;  // every script runs on this scene; the drag moves the subject
    const Scene scene =
        args.dense ? makeDenseScene({.boxes = cubes, .seed = args.seed}) : makeCubesScene(options);
    const auto buildStart = Clock::now();
    EngineSettings settings;
    settings.umbraCulling = args.umbraCulling;
    Engine engine(scene, settings);
    const double buildSeconds = secondsSince(buildStart);
    std::printf("N = %d %s: %zu faces, %zu receivers, build %.3f s\n", cubes,
                args.dense ? "dense boxes" : "cubes", scene.faces().size(),
                engine.receivers().size(), buildSeconds);
    std::fflush(stdout);

    const Budget budget = budgetFor(cubes, args);
    std::vector<EditScript> scripts{args.dense ? denseDragScript(scene, budget.drag, args.seed)
                                               : dragScript(scene, budget.drag, args.seed)};
    if (budget.shareFrames > 0)
      for (double share : {0.01, 0.05, 0.10, 0.30})
        if (share <= budget.maxShare)
          scripts.push_back(moveShareScript(scene, share, budget.shareFrames, args.seed));
    if (budget.removeAddPairs > 0)
      scripts.push_back(removeAddScript(scene, budget.removeAddPairs, args.seed));
    if (budget.buildUp > 0) scripts.push_back(buildUpScript(scene, budget.buildUp));

    // Scripts run one after the other on the same engine; each was generated from
    // the original scene and uses absolute transforms, so each applies as written.
    json results = json::array();
    const int rebuildEvery = rebuildEveryFor(cubes, args);
    for (const EditScript& script : scripts)
      results.push_back(runScript(engine, script, rebuildEvery));
    scenes.push_back({{"cubes", cubes},
                      {"scene", args.dense ? "dense" : "sparse"},
                      {"subject_cube", !args.dense},
                      {"rebuild_every", rebuildEvery},
                      {"faces", scene.faces().size()},
                      {"receivers", engine.receivers().size()},
                      {"build_seconds", buildSeconds},
                      {"scripts", std::move(results)}});
  }
  json result = {{"benchmark", "edits"}, {"scenes_kind", args.dense ? "dense" : "cubes"},
                 {"seed", args.seed},    {"light_scale", args.lightScale},
                 {"scenes", scenes},     {"drag_vs_size", dragVsSize(scenes)}};
  if (!args.htmlOut.empty()) {
    protocol::writeTextFile(args.htmlOut, editsReportHtml(result));
    std::printf("wrote %s\n", args.htmlOut.c_str());
  }
  return result;
}

}  // namespace penumbra::bench
