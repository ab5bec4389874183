// `penumbra-bench edits`: edit scripts (bench/lib/edit_scripts) applied frame by
// frame with Engine::apply on generated 'N cubes in a room' scenes, each frame
// against a full rebuild of the same scene (an Engine built from scratch, timed
// in the same run); JSON and a self-contained HTML report. With --write-scripts
// DIR --scene FILE it only writes that scene's standard scripts as .edits.jsonl.
#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <numeric>

#include "bench/bench_args.h"
#include "bench/lib/cubes_scene.h"
#include "bench/lib/edit_scripts.h"
#include "bench/report/edits_report_html.h"
#include "core/engine/engine.h"
#include "protocol/edits_json.h"
#include "protocol/json_text.h"
#include "protocol/scene_json.h"

namespace penumbra::bench {

namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Frames per script by scene size: every frame costs a full rebuild (and, until
// the incremental apply lands, a second one inside apply).
// Large moved shares cost minutes per frame at N = 1500 (2026-11: 30% took 5 min),
// so only small scenes run them by default.
struct Budget {
  int drag, shareFrames;
  double maxShare;
  int removeAddPairs, buildUp;
};
Budget budgetFor(int cubes, const BenchArgs& args) {
  Budget b = cubes <= 200    ? Budget{100, 5, 0.30, 5, 40}
             : cubes <= 2000 ? Budget{5, 1, 0.01, 0, 0}
                             : Budget{2, 0, 0, 0, 0};
  if (args.frames > 0) b.drag = args.frames;
  return b;
}

json runScript(Engine& engine, const EditScript& script) {
  json frames = json::array();
  double edit = 0, rebuild = 0, relit = 0, changed = 0, treeRebuilds = 0;
  for (size_t i = 0; i < script.frames.size(); ++i) {
    const auto wallStart = Clock::now();
    const FrameResult result = engine.apply(script.frames[i]);
    const double wall = secondsSince(wallStart);
    const auto rebuildStart = Clock::now();
    { const Engine rebuilt(engine.scene()); }
    const double rebuildSeconds = secondsSince(rebuildStart);
    edit += result.seconds.total();
    rebuild += rebuildSeconds;
    relit += double(result.verticesRelit);
    changed += double(result.verticesChanged);
    treeRebuilds += double(result.treeRebuilds);
    frames.push_back({{"frame", i + 1},
                      {"seconds",
                       {{"remove", result.seconds.remove},
                        {"add", result.seconds.add},
                        {"relight", result.seconds.relight},
                        {"total", result.seconds.total()}}},
                      {"wall_seconds", wall},
                      {"rebuild_seconds", rebuildSeconds},
                      {"edit_over_rebuild", result.seconds.total() / rebuildSeconds},
                      {"vertices",
                       {{"relit", result.verticesRelit},
                        {"changed", result.verticesChanged},
                        {"created", result.verticesCreated}}},
                      {"changed_receivers", result.changedReceivers.size()},
                      {"tree_rebuilds", result.treeRebuilds},
                      {"nodes_deleted", result.nodesDeleted}});
  }
  const double n = std::max<double>(1, double(script.frames.size()));
  std::printf(
      "  %-12s %4zu frames  %6zu faces (%5.1f%%)  edit %9.2f ms  rebuild %9.2f ms  ratio %6.3f  "
      "relit %9.0f  changed %9.0f\n",
      script.name.c_str(), script.frames.size(), script.editedFaces, 100 * script.faceShare,
      1e3 * edit / n, 1e3 * rebuild / n, rebuild > 0 ? edit / rebuild : 0.0, relit / n,
      changed / n);
  std::fflush(stdout);
  return {{"name", script.name},
          {"edited_faces", script.editedFaces},
          {"face_share", script.faceShare},
          {"mean_edit_seconds", edit / n},
          {"mean_rebuild_seconds", rebuild / n},
          {"edit_over_rebuild", rebuild > 0 ? edit / rebuild : 0.0},
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
    const Scene scene = makeCubesScene(options);
    const auto buildStart = Clock::now();
    Engine engine(scene);
    const double buildSeconds = secondsSince(buildStart);
    std::printf("N = %d cubes: %zu faces, %zu receivers, build %.3f s\n", cubes,
                scene.faces().size(), engine.receivers().size(), buildSeconds);
    std::fflush(stdout);

    const Budget budget = budgetFor(cubes, args);
    std::vector<EditScript> scripts{dragScript(scene, budget.drag, args.seed)};
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
    for (const EditScript& script : scripts) results.push_back(runScript(engine, script));
    scenes.push_back({{"cubes", cubes},
                      {"faces", scene.faces().size()},
                      {"receivers", engine.receivers().size()},
                      {"build_seconds", buildSeconds},
                      {"scripts", std::move(results)}});
  }
  json result = {{"benchmark", "edits"},
                 {"seed", args.seed},
                 {"light_scale", args.lightScale},
                 {"scenes", scenes}};
  if (!args.htmlOut.empty()) {
    protocol::writeTextFile(args.htmlOut, editsReportHtml(result));
    std::printf("wrote %s\n", args.htmlOut.c_str());
  }
  return result;
}

}  // namespace penumbra::bench
