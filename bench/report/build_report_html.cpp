#include "bench/report/build_report_html.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <vector>

#include "bench/report/build_summary.h"
#include "bench/report/html_page.h"
#include "bench/report/svg_charts.h"

namespace penumbra::bench {

namespace {

using nlohmann::json;

double number(const json& value) { return value.is_number() ? value.get<double>() : NAN; }

std::string fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "–";
  char text[48];
  std::snprintf(text, sizeof text, "%.*f", decimals, v);
  return text;
}

std::string cell(const std::string& text) { return "<td>" + escapeHtml(text) + "</td>"; }

std::string headerRow(const std::vector<std::string>& columns) {
  std::string out = "<tr>";
  for (const std::string& c : columns) out += "<th>" + escapeHtml(c) + "</th>";
  return out + "</tr>\n";
}

// One entry per scene (scene, cubes, light scale) in the rows' order, with its row at
// each thread count (null where that build failed).
struct SceneRows {
  const json* first = nullptr;  // any row of the scene, for its label and counters
  std::vector<const json*> byThreads;
};

std::vector<SceneRows> scenesOf(const json& result) {
  std::vector<SceneRows> out;
  const json& threads = result["threads"];
  auto same = [](const json& a, const json& b) {
    return a["scene"] == b["scene"] && a["cubes"] == b["cubes"] &&
           a["light_scale"] == b["light_scale"];
  };
  for (const json& row : result["rows"]) {
    auto found = std::find_if(out.begin(), out.end(),
                              [&](const SceneRows& s) { return same(*s.first, row); });
    if (found == out.end()) {
      out.push_back({&row, std::vector<const json*>(threads.size(), nullptr)});
      found = out.end() - 1;
    }
    for (size_t t = 0; t < threads.size(); ++t)
      if (row["threads"] == threads[t]) found->byThreads[t] = &row;
  }
  return out;
}

// ", load average 9.7 at the start and 10.1 at the end of the run" when recorded.
std::string loadText(const json& result) {
  const json load = result.value("load_average", json());
  if (!load.is_array() || load.size() != 2 || !load[0].is_number() || !load[1].is_number())
    return "";
  return "; 1-minute load average " + fixed(load[0].get<double>(), 1) + " at the start and " +
         fixed(load[1].get<double>(), 1) +
         " at the end of the run (above the hardware threads, wall times include waiting for a "
         "core "
         "and the speed-up is understated; compare the CPU seconds)";
}

std::string threadsName(const json& threads) {
  const int t = threads.get<int>();
  return t == 0 ? "all threads" : t == 1 ? "1 thread" : std::to_string(t) + " threads";
}

}  // namespace

std::vector<std::string> buildSummaryColumns(const json& threads) {
  std::vector<std::string> columns{"N (sparse/dense)", "faces"};
  for (const json& t : threads) columns.push_back("build s, " + threadsName(t));
  const auto& labels = buildStepLabels();
  for (size_t i = 0; i + 1 < labels.size(); ++i) columns.push_back(labels[i] + " s");
  columns.push_back("peak MiB");
  columns.push_back("vertices");
  return columns;
}

namespace {

std::string summaryTable(const json& result, const std::vector<SceneRows>& scenes) {
  std::string out = "<table class='summary'>\n" + headerRow(buildSummaryColumns(result["threads"]));
  for (const SceneRows& s : scenes) {
    const json* base = s.byThreads.front();
    out += "<tr>" + cell(sceneLabel(*s.first)) +
           cell(std::to_string(s.first->at("faces").get<size_t>()));
    for (const json* row : s.byThreads)
      out += cell(row ? fixed(row->at("seconds")["build_and_mesh"].get<double>(), 3) : "failed");
    const auto& keys = buildStepKeys();
    for (size_t i = 0; i + 1 < keys.size(); ++i)
      out += cell(base ? fixed(base->at("seconds")[keys[i]].get<double>(), 3) : "–");
    out += cell(base ? fixed(base->at("peak_memory_mib").get<double>(), 0) : "–");
    out += cell(std::to_string(s.first->at("vertices").get<size_t>())) + "</tr>\n";
  }
  return out + "</table>\n";
}

std::string speedupTable(const json& result) {
  if (result["speedup"].empty()) return "<p>One thread count only: no speed-up measured.</p>\n";
  std::vector<std::string> columns{"N (sparse/dense)", "threads"};
  for (const std::string& label : buildStepLabels()) columns.push_back(label);
  columns.push_back("build + mesh CPU s");
  std::string out = "<table class='speedup'>\n" + headerRow(columns);
  for (const json& entry : result["speedup"]) {
    out += "<tr>" + cell(sceneLabel(entry)) +
           cell(std::to_string(entry["from_threads"].get<int>()) + " → " +
                std::to_string(entry["to_threads"].get<int>()));
    for (const std::string& key : buildStepKeys()) {
      const json& seconds = entry["seconds"][key];
      out += cell(fixed(number(seconds[0]), 3) + " → " + fixed(number(seconds[1]), 3) + " s (" +
                  fixed(number(entry["speedup"][key]), 2) + "×)");
    }
    const json& cpu = entry["cpu_seconds"];
    out += cell(fixed(number(cpu[0]), 3) + " → " + fixed(number(cpu[1]), 3));
    out += "</tr>\n";
  }
  return out + "</table>\n";
}

std::string memoryTable(const json& result, const std::vector<SceneRows>& scenes) {
  std::vector<std::string> columns{"N (sparse/dense)", "faces"};
  for (const json& t : result["threads"]) columns.push_back("peak MiB, " + threadsName(t));
  columns.push_back("kB per face");
  columns.push_back("peak MiB with a flat mesh copy, " + threadsName(result["threads"].front()));
  columns.push_back("vertices");
  columns.push_back("mesh vertices");
  std::string out = "<table class='memory'>\n" + headerRow(columns);
  for (const SceneRows& s : scenes) {
    const json* base = s.byThreads.front();
    out += "<tr>" + cell(sceneLabel(*s.first)) +
           cell(std::to_string(s.first->at("faces").get<size_t>()));
    for (const json* row : s.byThreads)
      out += cell(row ? fixed(row->at("peak_memory_mib").get<double>(), 0) : "failed");
    out += cell(base ? fixed(base->at("kb_per_face").get<double>(), 1) : "–") +
           cell(base ? fixed(base->value("peak_with_flat_mesh_mib", NAN), 0) : "–") +
           cell(std::to_string(s.first->at("vertices").get<size_t>())) +
           cell(std::to_string(s.first->at("mesh_vertices").get<size_t>())) + "</tr>\n";
  }
  return out + "</table>\n";
}

// Sparse (light 1): blue, sparse light 0.2: green, dense: red, in every plot.
int kindColour(const std::string& scene, double lightScale) {
  return scene == "dense" ? 1 : lightScale == 1.0 ? 0 : 2;
}

// Series of y(row) against N: one colour per scene kind (sparse light 1, sparse light
// 0.2, dense), solid at the first thread count, dashed at the others.
std::vector<Series> seriesByScene(const json& result, double (*y)(const json&), bool allThreads) {
  std::vector<Series> out;
  std::vector<std::tuple<std::string, double, int>> keys;
  for (const json& row : result["rows"]) {
    const int threads = row["threads"].get<int>();
    if (!allThreads && threads != result["threads"][0].get<int>()) continue;
    const std::tuple<std::string, double, int> key{row["scene"].get<std::string>(),
                                                   row["light_scale"].get<double>(), threads};
    size_t k = std::find(keys.begin(), keys.end(), key) - keys.begin();
    if (k == keys.size()) {
      keys.push_back(key);
      std::string name = sceneKindLabel(std::get<0>(key), std::get<1>(key));
      if (allThreads) name += ", " + threadsName(row["threads"]);
      const bool first = threads == result["threads"][0].get<int>();
      out.push_back({name, {}, !first, false, kindColour(std::get<0>(key), std::get<1>(key))});
    }
    out[k].points.emplace_back(row["cubes"].get<double>(), y(row));
  }
  return out;
}

std::string growthText(const json& result) {
  std::string out;
  for (const json& series : result["growth"]) {
    std::string ks;
    for (const json& p : series["points"])
      if (p["exponent"].is_number())
        ks += (ks.empty() ? "" : ", ") + fixed(p["exponent"].get<double>(), 2);
    if (ks.empty()) continue;
    out += "<br>" +
           escapeHtml(sceneKindLabel(series["scene"], series["light_scale"].get<double>())) + ", " +
           threadsName(series["threads"]) + ": " + ks;
  }
  if (out.empty()) return "";
  return "<p>Growth exponents k, build + mesh time ∝ faces<sup>k</sup> between consecutive sizes:" +
         out + "</p>\n";
}

// Speed-up vs N per scene kind (one colour each): the whole build (solid), illumination
// (dashed) and casting + merging (markers); every step is in the table.
std::string speedupPlot(const json& result) {
  Plot plot{"Speed-up over " + threadsName(result["threads"][0]),
            "N (cubes or boxes)",
            "speed-up",
            true,
            false,
            {},
            false,
            260};
  const std::vector<std::pair<std::string, std::string>> steps{{"build_and_mesh", "build + mesh"},
                                                               {"illumination", "illumination"},
                                                               {"casting_and_merging", "casting"}};
  for (const json& entry : result["speedup"]) {
    const double lightScale = entry["light_scale"].get<double>();
    const std::string kind = sceneKindLabel(entry["scene"], lightScale);
    for (size_t k = 0; k < steps.size(); ++k) {
      const std::string name =
          kind + ": " + steps[k].second + ", " + threadsName(entry["to_threads"]);
      auto found = std::find_if(plot.series.begin(), plot.series.end(),
                                [&](const Series& s) { return s.name == name; });
      if (found == plot.series.end()) {
        plot.series.push_back({name, {}, k == 1, k == 2, kindColour(entry["scene"], lightScale)});
        found = plot.series.end() - 1;
      }
      found->points.emplace_back(entry["cubes"].get<double>(),
                                 number(entry["speedup"][steps[k].first]));
    }
  }
  return svgPlot(plot);
}

std::string plots(const json& result, const std::vector<SceneRows>& scenes) {
  Plot time{"Build + mesh time vs N", "N (cubes or boxes)", "seconds", true, true, {}, false, 210};
  time.series = seriesByScene(
      result, [](const json& r) { return r["seconds"]["build_and_mesh"].get<double>(); }, true);
  StackedBars split{"Time per step at " + threadsName(result["threads"][0]), "s", {}, {}};
  const auto& labels = buildStepLabels();
  split.parts.assign(labels.begin(), labels.end() - 1);
  for (const SceneRows& s : scenes) {
    if (!s.byThreads.front()) continue;
    std::vector<double> values;
    for (size_t i = 0; i + 1 < buildStepKeys().size(); ++i)
      values.push_back(s.byThreads.front()->at("seconds")[buildStepKeys()[i]].get<double>());
    split.bars.emplace_back(sceneLabel(*s.first), values);
  }
  Plot memory{"Peak memory vs N", "N (cubes or boxes)", "MiB", true, true, {}, false, 210};
  memory.series = seriesByScene(
      result, [](const json& r) { return r["peak_memory_mib"].get<double>(); }, true);
  Plot perFace{
      "Peak memory per input face", "N (cubes or boxes)", "kB per face", true, false, {}, false};
  perFace.series = seriesByScene(
      result, [](const json& r) { return r["kb_per_face"].get<double>(); }, false);
  Plot vertices{"DM vertices vs N", "N (cubes or boxes)", "vertices", true, true, {}, false};
  vertices.series = seriesByScene(
      result, [](const json& r) { return r["vertices"].get<double>(); }, false);
  return svgPlot(time) + growthText(result) + svgStackedBars(split) + speedupPlot(result) +
         svgPlot(memory) + svgPlot(perFace) + svgPlot(vertices);
}

}  // namespace

std::string buildReportHtml(const json& result) {
  const std::vector<SceneRows> scenes = scenesOf(result);
  std::string html =
      "<p>Generated scenes (seed " + result["seed"].dump() +
      "): <em>sparse</em> is \"N cubes in a room\" (<code>penumbra generate</code>) at light "
      "scales 1 and 0.2, <em>dense</em> is N boxes floating in a 6 × 3 × 6 m room under one "
      "light (<code>penumbra generate --dense</code>). Every row is one build (Engine + mesh) in "
      "its own process (<code>penumbra-bench build-row</code>), so its peak resident memory "
      "(getrusage, read right after the build) is its own; it includes the process's "
      "baseline. Times are wall seconds; the steps are the engine's BuildStats. The machine "
      "has " +
      result["hardware_threads"].dump() + " hardware threads" + loadText(result) + ".</p>\n";
  html += "<h2>Summary</h2>\n" + summaryTable(result, scenes);
  html += "<h2>Threads: wall seconds per step and speed-up</h2>\n" + speedupTable(result);
  html += "<h2>Memory and vertices</h2>\n" + memoryTable(result, scenes);
  html += plots(result, scenes);
  if (!result["failures"].empty())
    html += "<h2>Failed builds</h2>\n<pre>" + escapeHtml(result["failures"].dump(1)) + "</pre>\n";
  return htmlPage("Penumbra: discontinuity-mesh build, sparse and dense rooms", html, result);
}

}  // namespace penumbra::bench
