#include "bench/report/edits_report_html.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench/report/html_page.h"
#include "bench/report/svg_charts.h"

namespace penumbra::bench {

namespace {

using nlohmann::json;

const json* script(const json& scene, const std::string& name) {
  for (const json& s : scene["scripts"])
    if (s["name"] == name) return &s;
  return nullptr;
}

double ms(const json& seconds) { return seconds.is_number() ? 1e3 * seconds.get<double>() : NAN; }

// "N=150: 1, N=5000: 10" from the scenes' rebuild_every (1 when absent).
std::string rebuildEveryText(const json& result) {
  std::string out;
  for (const json& scene : result["scenes"])
    out += (out.empty() ? "" : ", ") + std::string("N=") +
           std::to_string(scene["cubes"].get<int>()) + ": " +
           std::to_string(scene.value("rebuild_every", 1));
  return out;
}

// Percent of a ratio field, NAN when absent or null.
double percent(const json& size, const char* key) {
  const json value = size.value(key, json());
  return value.is_number() ? 100 * value.get<double>() : NAN;
}

const char* kCubesDragText =
    "<h2>Dragging the same cube at every scene size</h2>\n<p>The subject cube "
    "(<code>cube_subject</code>): 0.5 m, standing on the floor 1.5 m along +x from the "
    "light's centre, turned 20°, in every scene; its corridor is kept clear by the generator. "
    "It slides in steps of 8 cm tangentially to the circle round the light (the same path at "
    "every N), turning 0.5° a step. The first frame also removes nodes the cube's shadow "
    "inserted early in the receivers' trees, so the median is the measure.</p>\n";
const char* kDenseDragText =
    "<h2>Moving one box in the dense rooms</h2>\n<p>The box closest to the middle of the room "
    "under the light (its shadow falls on the floor under the light and on the boxes below) "
    "slides horizontally in steps of 2 cm along a direction whose swept bounding sphere stays "
    "clear of every other box, turning 0.5° a step (<code>bench/lib/dense_drag.h</code>). "
    "Issue 11: moving one box in dense N = 1,500 costs ≤ 2% of its build, first move "
    "included — the <em>first / rebuild</em> column.</p>\n";

// Issue 4's measure: the drag per scene size (first frame, median, mean) and the
// median ratio of the largest scene over the smallest; issue 11's: each over the rebuild.
std::string dragTable(const json& result) {
  if (!result.contains("drag_vs_size")) return "";
  const json& summary = result["drag_vs_size"];
  const bool dense = result.value("scenes_kind", "cubes") == "dense";
  std::string out =
      std::string(dense ? kDenseDragText : kCubesDragText) + "<table class='drag'><tr><th>" +
      (dense ? "boxes" : "cubes") + "</th><th>" + (dense ? "box" : "cube") +
      " dragged</th><th>frames</th><th>first ms</th>"
      "<th>median ms</th><th>mean ms</th><th>median wall ms</th><th>median rebuild ms</th>"
      "<th>rebuilds timed</th><th>first / rebuild %</th><th>median / rebuild %</th>"
      "<th>mean / rebuild %</th></tr>\n";
  for (const json& size : summary["sizes"]) {
    char row[1024];
    std::snprintf(row, sizeof row,
                  "<tr><td>%d</td><td style='text-align:left'>%s</td><td>%zu</td><td>%.2f</td>"
                  "<td>%.2f</td><td>%.2f</td><td>%.2f</td><td>%.2f</td><td>%zu</td>"
                  "<td>%.2f</td><td>%.2f</td><td>%.2f</td></tr>\n",
                  size["cubes"].get<int>(), escapeHtml(size["subject"].get<std::string>()).c_str(),
                  size["frames"].get<size_t>(), ms(size["first_edit_seconds"]),
                  ms(size["median_edit_seconds"]), ms(size["mean_edit_seconds"]),
                  ms(size.value("median_wall_seconds", json())), ms(size["median_rebuild_seconds"]),
                  size.value("rebuild_frames", size_t(0)), percent(size, "first_over_rebuild"),
                  percent(size, "median_over_rebuild"), percent(size, "mean_over_rebuild"));
    out += row;
  }
  out += "</table>\n";
  const json& ratio = summary["median_ratio"];
  if (ratio.is_object() && ratio["ratio"].is_number()) {
    char line[512];
    const json wall = ratio.value("wall_ratio", json());
    std::snprintf(
        line, sizeof line,
        "<p>Median edit time, N = %d over N = %d: <b>%.2f×</b> (issue 4, sparse rooms: at "
        "most 2× from 150 to 5000); wall time of Engine::apply (also checking the frame on a copy "
        "of "
        "the scene, outside the remove / add / relight split): %.2f×.</p>\n",
        ratio["to_cubes"].get<int>(), ratio["from_cubes"].get<int>(), ratio["ratio"].get<double>(),
        wall.is_number() ? wall.get<double>() : NAN);
    out += line;
  }
  return out;
}

// What the scenes and the timings are.
std::string introHtml(const json& result) {
  const bool dense = result.value("scenes_kind", "cubes") == "dense";
  return std::string(dense ? "<p>Generated dense rooms (N boxes floating in a 6 × 3 × 6 m room, "
                             "one light; seed "
                           : "<p>Generated \"N cubes in a room\" scenes (seed ") +
         result["seed"].dump() +
         (dense
              ? "); one box is dragged (below) on one engine. Edit"
              : "), each with N generated objects plus the subject cube <code>cube_subject</code>; "
                "every script (drag, moved shares, remove-add, build-up) runs on that same scene, "
                "one after the other on one engine. Edit") +
         " time is Engine::apply's own split (remove + add + relight); the full rebuild is an "
         "Engine "
         "built from scratch on the same scene in the "
         "same run, timed after the first frame, every K-th and the last (K per N: " +
         rebuildEveryText(result) +
         "); rebuild means and medians are over the timed frames. A frame that "
         "Engine::apply turns into a full rebuild (large moved shares) counts every receiver "
         "in <em>tree rebuilds / frame</em>.</p>\n";
}

}  // namespace

std::string editsReportHtml(const json& result) {
  // title, x label, y label, log x, log y, series, y = x
  Plot drag{"Dragging one object: edit vs full rebuild, per frame",
            "frame",
            "milliseconds",
            false,
            true,
            {},
            false};
  Plot shares{"Moving a share of the faces together (mean per frame)",
              "share of the scene's faces (%)",
              "milliseconds",
              false,
              true,
              {},
              false};
  Plot sizes{"Dragging one object: median time per frame vs scene size",
             "faces in the scene",
             "milliseconds per frame",
             true,
             true,
             {},
             false};
  Plot relit{"Vertices relit vs vertices whose value changed (every frame)",
             "vertices changed",
             "vertices relit",
             true,
             true,
             {},
             true};
  Series sizeEdit{"edit (apply), median", {}}, sizeRebuild{"full rebuild, median", {}, true};
  Series sizeFirst{"edit, first frame", {}, false, true};
  Series relitPoints{"frames", {}, false, true};

  std::string table =
      "<table><tr><th>cubes</th><th>faces</th><th>build "
      "s</th><th>script</th><th>frames</th><th>edited faces</th>"
      "<th>share %</th><th>mean edit ms</th><th>mean rebuild ms</th><th>edit / "
      "rebuild</th><th>relit / frame</th>"
      "<th>changed / frame</th><th>tree rebuilds / frame</th><th>full-rebuild frames</th></tr>\n";
  for (const json& scene : result["scenes"]) {
    const std::string n = "N=" + std::to_string(scene["cubes"].get<int>());
    const double faces = scene["faces"].get<double>();
    if (const json* d = script(scene, "drag")) {
      Series edit{"edit " + n, {}}, rebuild{"rebuild " + n, {}, true};
      for (const json& f : (*d)["frames"]) {
        edit.points.emplace_back(f["frame"].get<double>(), ms(f["seconds"]["total"]));
        rebuild.points.emplace_back(f["frame"].get<double>(), ms(f["rebuild_seconds"]));
      }
      drag.series.push_back(std::move(edit));
      drag.series.push_back(std::move(rebuild));
      sizeEdit.points.emplace_back(faces, ms((*d)["median_edit_seconds"]));
      sizeRebuild.points.emplace_back(faces, ms((*d)["median_rebuild_seconds"]));
      sizeFirst.points.emplace_back(faces, ms((*d)["first_edit_seconds"]));
    }
    Series shareEdit{"edit " + n, {}}, shareRebuild{"rebuild " + n, {}, true};
    for (const json& s : scene["scripts"]) {
      const std::string name = s["name"];
      if (name.rfind("move-", 0) == 0) {
        shareEdit.points.emplace_back(100 * s["face_share"].get<double>(),
                                      ms(s["mean_edit_seconds"]));
        shareRebuild.points.emplace_back(100 * s["face_share"].get<double>(),
                                         ms(s["mean_rebuild_seconds"]));
      }
      for (const json& f : s["frames"])
        relitPoints.points.emplace_back(f["vertices"]["changed"].get<double>(),
                                        f["vertices"]["relit"].get<double>());
      char row[512];
      std::snprintf(
          row, sizeof row,
          "<tr><td>%d</td><td>%.0f</td><td>%.3f</td><td>%s</td><td>%zu</td><td>%zu</td><td>%.1f</"
          "td>"
          "<td>%.2f</td><td>%.2f</td><td>%.3f</td><td>%.0f</td><td>%.0f</td><td>%.0f</td>"
          "<td>%zu</td></tr>\n",
          scene["cubes"].get<int>(), faces, scene["build_seconds"].get<double>(), name.c_str(),
          s["frames"].size(), s["edited_faces"].get<size_t>(), 100 * s["face_share"].get<double>(),
          ms(s["mean_edit_seconds"]), ms(s["mean_rebuild_seconds"]),
          s["edit_over_rebuild"].get<double>(), s["mean_relit"].get<double>(),
          s["mean_changed"].get<double>(), s["mean_tree_rebuilds"].get<double>(),
          s.value("full_rebuild_frames", size_t(0)));
      table += row;
    }
    if (!shareEdit.points.empty()) {
      shares.series.push_back(std::move(shareEdit));
      shares.series.push_back(std::move(shareRebuild));
    }
  }
  table += "</table>\n";
  sizes.series = {sizeEdit, sizeRebuild, sizeFirst};
  relit.series = {relitPoints};

  return htmlPage("Penumbra: incremental edits vs full rebuild",
                  introHtml(result) + table + dragTable(result) + svgPlot(drag) + svgPlot(shares) +
                      svgPlot(sizes) + svgPlot(relit),
                  result);
}

}  // namespace penumbra::bench
