#include "bench/report/build_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <thread>
#include <tuple>

namespace penumbra::bench {

using nlohmann::json;

namespace {

// Rows of one scene at its thread counts: the key leaves out the threads.
using SceneKey = std::tuple<std::string, int, double>;
SceneKey sceneKey(const json& row) {
  return {row["scene"].get<std::string>(), row["cubes"].get<int>(),
          row["light_scale"].get<double>()};
}

const json* rowAt(const json& rows, const SceneKey& key, int threads) {
  for (const json& row : rows)
    if (sceneKey(row) == key && row["threads"].get<int>() == threads) return &row;
  return nullptr;
}

}  // namespace

const std::vector<std::string>& buildStepKeys() {
  static const std::vector<std::string> keys{"ordering",     "cube",          "casting_and_merging",
                                             "illumination", "triangulation", "build_and_mesh"};
  return keys;
}

const std::vector<std::string>& buildStepLabels() {
  static const std::vector<std::string> labels{"ordering",     "cube",          "casting + merging",
                                               "illumination", "triangulation", "build + mesh"};
  return labels;
}

namespace {

std::string lightSuffix(double lightScale) {
  if (lightScale == 1.0) return "";
  char text[32];
  std::snprintf(text, sizeof text, ", light ×%g", lightScale);
  return text;
}

}  // namespace

std::string sceneLabel(const json& row) {
  return row["scene"].get<std::string>() + " " + std::to_string(row["cubes"].get<int>()) +
         lightSuffix(row["light_scale"].get<double>());
}

std::string sceneKindLabel(const std::string& scene, double lightScale) {
  return scene + lightSuffix(lightScale);
}

json threadSpeedups(const json& rows, const std::vector<int>& threads) {
  json out = json::array();
  if (threads.size() < 2) return out;
  std::vector<SceneKey> scenes;
  for (const json& row : rows)
    if (std::find(scenes.begin(), scenes.end(), sceneKey(row)) == scenes.end())
      scenes.push_back(sceneKey(row));
  for (const SceneKey& key : scenes) {
    const json* from = rowAt(rows, key, threads.front());
    for (size_t i = 1; from && i < threads.size(); ++i) {
      const json* to = rowAt(rows, key, threads[i]);
      if (!to) continue;
      json seconds = json::object(), speedup = json::object();
      for (const std::string& step : buildStepKeys()) {
        const double a = (*from)["seconds"][step].get<double>(),
                     b = (*to)["seconds"][step].get<double>();
        seconds[step] = {a, b};
        speedup[step] = b > 0 ? json(a / b) : json(nullptr);
      }
      out.push_back(
          {{"scene", std::get<0>(key)},
           {"cubes", std::get<1>(key)},
           {"light_scale", std::get<2>(key)},
           {"from_threads", threads.front()},
           {"to_threads", threads[i]},
           {"seconds", seconds},
           {"cpu_seconds",
            {(*from)["seconds"]["build_and_mesh_cpu"], (*to)["seconds"]["build_and_mesh_cpu"]}},
           {"speedup", speedup}});
    }
  }
  return out;
}

json buildGrowth(const json& rows) {
  std::map<std::tuple<std::string, double, int>, std::vector<const json*>> series;
  for (const json& row : rows)
    series[{row["scene"].get<std::string>(), row["light_scale"].get<double>(),
            row["threads"].get<int>()}]
        .push_back(&row);
  json out = json::array();
  for (auto& [key, members] : series) {
    std::sort(members.begin(), members.end(), [](const json* a, const json* b) {
      return (*a)["cubes"].get<int>() < (*b)["cubes"].get<int>();
    });
    json points = json::array();
    for (size_t i = 0; i < members.size(); ++i) {
      const json& row = *members[i];
      const double faces = row["faces"].get<double>(),
                   seconds = row["seconds"]["build_and_mesh"].get<double>();
      json exponent = nullptr;
      if (i > 0) {
        const double f0 = (*members[i - 1])["faces"].get<double>();
        const double s0 = (*members[i - 1])["seconds"]["build_and_mesh"].get<double>();
        if (f0 > 0 && faces > f0 && s0 > 0 && seconds > 0)
          exponent = std::log(seconds / s0) / std::log(faces / f0);
      }
      points.push_back({{"cubes", row["cubes"]},
                        {"faces", row["faces"]},
                        {"seconds", seconds},
                        {"exponent", exponent}});
    }
    out.push_back({{"scene", std::get<0>(key)},
                   {"light_scale", std::get<1>(key)},
                   {"threads", std::get<2>(key)},
                   {"points", points}});
  }
  return out;
}

json buildBenchResult(const json& rows, const json& failures, const std::vector<int>& threads,
                      uint64_t seed) {
  bool sparse = false, dense = false;
  for (const json& row : rows) (row["scene"] == "dense" ? dense : sparse) = true;
  return {{"benchmark", "build"},
          {"scenes", sparse && dense ? "cubes+dense"
                     : dense         ? "dense"
                                     : "cubes"},
          {"seed", seed},
          {"threads", threads},
          {"hardware_threads", std::thread::hardware_concurrency()},
          {"rows", rows},
          {"failures", failures},
          {"speedup", threadSpeedups(rows, threads)},
          {"growth", buildGrowth(rows)}};
}

}  // namespace penumbra::bench
