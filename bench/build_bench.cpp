// `penumbra-bench build`: the full discontinuity-mesh build on generated scenes — sparse
// 'N cubes in a room' at two light sizes (--cubes) and dense 'N boxes floating in a room',
// one light (--dense-cubes, or --cubes with --dense) — each scene at each --threads count,
// each build in its own child process (`penumbra-bench build-row`, bench/build_row.cpp)
// so every row's peak memory is its own. Prints a table, returns the rows with the
// speed-up per step and the growth with N; --html writes the report.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/bench_args.h"
#include "bench/child_process.h"
#include "bench/report/build_report_html.h"
#include "bench/report/build_summary.h"
#include "protocol/json_text.h"
#include "scenegen/model_scene.h"

namespace penumbra::bench {

namespace {

using nlohmann::json;

struct RowSpec {
  std::string model;  // empty: a cubes or dense room
  bool dense = false;
  int cubes = 0;
  double lightScale = 1;
  int threads = 1;
  bool compare = true;  // Monte Carlo and mesh quality: at the first thread count only
};

// Sparse rows: --cubes (unless only --dense-cubes or --model was given) at light scales 1
// and 0.2; dense rows: --dense-cubes, or --cubes with --dense (one light size); model rows:
// each --model at each --triangles (`cubes` holds the count asked for).
std::vector<RowSpec> buildPlan(const BenchArgs& args) {
  std::vector<int> sparse, dense = args.denseCubes;
  if (args.dense)
    dense.insert(dense.begin(), args.cubes.begin(), args.cubes.end());
  else if (args.cubesGiven || (args.denseCubes.empty() && args.models.empty()))
    sparse = args.cubes;
  std::vector<RowSpec> plan;
  auto add = [&](bool isDense, int cubes, double lightScale) {
    for (size_t t = 0; t < args.threads.size(); ++t)
      plan.push_back({"", isDense, cubes, lightScale, args.threads[t], args.compare && t == 0});
  };
  for (const std::string& model : args.models)
    for (int triangles : args.triangles)
      for (size_t t = 0; t < args.threads.size(); ++t)
        plan.push_back(
            {model, false,
             triangles > 0 ? triangles : defaultModelTriangles(*modelKindFromName(model)), 1.0,
             args.threads[t], args.compare && t == 0});
  for (int cubes : sparse)
    for (double lightScale : {1.0, 0.2}) add(false, cubes, lightScale);
  for (int cubes : dense) add(true, cubes, 1.0);
  return plan;
}

std::vector<std::string> childArguments(const RowSpec& spec, const BenchArgs& args) {
  char scale[32];
  std::snprintf(scale, sizeof scale, "%.17g", spec.lightScale);
  std::vector<std::string> out{"build-row",
                               "--cubes",
                               std::to_string(spec.cubes),
                               "--threads",
                               std::to_string(spec.threads),
                               "--light-scale",
                               scale,
                               "--seed",
                               std::to_string(args.seed),
                               "--points",
                               std::to_string(args.points),
                               "--max-samples",
                               std::to_string(args.maxSamples),
                               "--quality-max-cubes",
                               std::to_string(args.qualityMaxCubes)};
  if (spec.dense) out.push_back("--dense");
  if (!spec.model.empty()) {
    out.insert(out.end(), {"--model", spec.model, "--triangles", std::to_string(spec.cubes)});
    if (args.rest) out.push_back("--rest");
  }
  if (!spec.compare) out.push_back("--no-compare");
  if (args.allLines) out.push_back("--all-lines");
  if (args.faceByFace) out.push_back("--face-by-face");
  if (!args.umbraCulling) out.push_back("--no-umbra-culling");
  return out;
}

// The 1-minute load average (/proc/loadavg), NAN where there is none: on a shared machine
// wall times include waiting for a core.
double loadAverage() {
  double load = NAN;
  if (FILE* file = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(file, "%lf", &load) != 1) load = NAN;
    std::fclose(file);
  }
  return load;
}

double number(const json& value) { return value.is_number() ? value.get<double>() : NAN; }

void printHeader() {
  std::printf(
      "%6s %6s %5s %3s %6s %8s %8s %7s %8s %8s %6s | %8s %8s %6s %6s %8s %7s %9s | %9s %8s %7s\n",
      "scene", "N", "light", "thr", "faces", "pairs", "shadows", "nodes", "vertices", "penumbra",
      "cmp/v", "build s", "cpu s", "cast%", "illum%", "peak MiB", "kB/face", "disp tri", "MC s",
      "MC/build", "DM/grid");
}

void printRow(const json& row) {
  const json& s = row["seconds"];
  double steps = 0;
  for (const char* key :
       {"ordering", "cube", "casting_and_merging", "illumination", "triangulation"})
    steps += s[key].get<double>();
  const json& mc = row["monte_carlo"];
  const json& quality = row["mesh_quality"];
  std::printf(
      "%6s %6d %5.1f %3d %6zu %8zu %8zu %7zu %8zu %8zu %6.2f | %8.3f %8.3f %5.0f%% %5.0f%% %8.0f "
      "%7.1f %9zu | "
      "%9.1f %8.0f %7.3f\n",
      row["scene"].get<std::string>().c_str(), row["cubes"].get<int>(),
      row["light_scale"].get<double>(), row["threads"].get<int>(), row["faces"].get<size_t>(),
      row["candidate_pairs"].get<size_t>(), row["pairs_with_shadow"].get<size_t>(),
      row["tree_nodes"].get<size_t>(), row["vertices"].get<size_t>(),
      row["penumbra_vertices"].get<size_t>(), row["comparisons_per_vertex"].get<double>(),
      s["build_and_mesh"].get<double>(), s["build_and_mesh_cpu"].get<double>(),
      100 * s["casting_and_merging"].get<double>() / steps,
      100 * s["illumination"].get<double>() / steps, row["peak_memory_mib"].get<double>(),
      row["kb_per_face"].get<double>(), row.value("display_triangles", size_t(0)),
      mc.is_object() ? number(mc["seconds_all_penumbra_vertices"]) : NAN,
      mc.is_object() ? number(mc["over_build"]) : NAN,
      quality.is_object() ? number(quality["dm_over_grid"]) : NAN);
  std::fflush(stdout);
}

void printSpeedups(const json& speedups) {
  for (const json& entry : speedups) {
    std::printf("speed-up %d → %d threads, %s:", entry["from_threads"].get<int>(),
                entry["to_threads"].get<int>(), sceneLabel(entry).c_str());
    for (size_t i = 0; i < buildStepKeys().size(); ++i)
      std::printf(" %s %.2f×%s", buildStepLabels()[i].c_str(),
                  number(entry["speedup"][buildStepKeys()[i]]),
                  i + 1 < buildStepKeys().size() ? "," : "\n");
  }
}

}  // namespace

json runBuildBench(const BenchArgs& args) {
  json rows = json::array(), failures = json::array();
  const double loadAtStart = loadAverage();
  printHeader();
  for (const RowSpec& spec : buildPlan(args)) {
    const ChildResult child = runSelf(childArguments(spec, args));
    json row;
    if (child.exitCode == 0) {  // the row is the child's last line
      const std::string& out = child.output;
      const size_t end = out.find_last_not_of('\n');
      const size_t start = end == std::string::npos ? 0 : out.rfind('\n', end);
      row = json::parse(out.substr(start == std::string::npos ? 0 : start), nullptr, false);
    }
    if (child.exitCode != 0 || row.is_discarded() || !row.is_object()) {
      // A scene that runs out of memory or crashes is a result too: note it, go on.
      const std::string scene = !spec.model.empty() ? spec.model : spec.dense ? "dense" : "sparse";
      std::printf("%6s %6d %5.1f %3d   failed (exit %d, signal %d)\n", scene.c_str(), spec.cubes,
                  spec.lightScale, spec.threads, child.exitCode, child.signal);
      failures.push_back({{"scene", scene},
                          {"cubes", spec.cubes},
                          {"light_scale", spec.lightScale},
                          {"threads", spec.threads},
                          {"exit_code", child.exitCode},
                          {"signal", child.signal}});
      continue;
    }
    printRow(row);
    rows.push_back(std::move(row));
  }
  json result = buildBenchResult(rows, failures, args.threads, args.seed);
  result["load_average"] = {loadAtStart, loadAverage()};
  printSpeedups(result["speedup"]);
  if (!args.htmlOut.empty()) {
    protocol::writeTextFile(args.htmlOut, buildReportHtml(result));
    std::printf("wrote %s\n", args.htmlOut.c_str());
  }
  return result;
}

}  // namespace penumbra::bench
