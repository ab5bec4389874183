// The build benchmark's report on a tiny real run (N = 5, sparse and dense, 1 and 2
// threads, built in this process): well-formed HTML, the summary table with issue 11's
// columns and one row per scene, a failed build shown as such, and the speed-up and
// growth summaries.
#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <vector>

#include "bench/bench_args.h"
#include "bench/report/build_report_html.h"
#include "bench/report/build_summary.h"

namespace penumbra::bench {
namespace {

using nlohmann::json;

// Every tag closed in order (void and self-closed ones aside), no stray '<' or '&'.
::testing::AssertionResult wellFormed(const std::string& html) {
  std::vector<std::string> open;
  for (size_t i = 0; i < html.size(); ++i) {
    if (html[i] == '&') {
      static const std::regex entity("^&(lt|gt|amp|quot|#[0-9]+);");
      if (!std::regex_search(html.substr(i, 8), entity))
        return ::testing::AssertionFailure() << "bare & at " << i;
      continue;
    }
    if (html[i] != '<') continue;
    const size_t end = html.find('>', i);
    if (end == std::string::npos) return ::testing::AssertionFailure() << "unclosed < at " << i;
    const std::string tag = html.substr(i + 1, end - i - 1);
    i = end;
    if (tag.empty() || tag[0] == '!' || tag.back() == '/') continue;
    const bool closing = tag[0] == '/';
    const std::string name = tag.substr(closing, tag.find_first_of(" \n", closing) - closing);
    if (!std::regex_match(name, std::regex("[a-z][a-z0-9]*")))
      return ::testing::AssertionFailure() << "bad tag <" << tag << ">";
    if (name == "meta" || name == "br") continue;
    if (!closing) {
      open.push_back(name);
    } else if (open.empty() || open.back() != name) {
      return ::testing::AssertionFailure()
             << "</" << name << "> closes <" << (open.empty() ? "nothing" : open.back()) << ">";
    } else {
      open.pop_back();
    }
  }
  if (!open.empty()) return ::testing::AssertionFailure() << "<" << open.back() << "> never closed";
  return ::testing::AssertionSuccess();
}

// The cells of each row of the table that starts with `<table class='NAME'>`.
std::vector<std::vector<std::string>> tableCells(const std::string& html, const std::string& name) {
  const size_t start = html.find("<table class='" + name + "'>");
  const size_t end = html.find("</table>", start);
  std::vector<std::vector<std::string>> rows;
  if (start == std::string::npos || end == std::string::npos) return rows;
  const std::string table = html.substr(start, end - start);
  static const std::regex row("<tr>(.*?)</tr>"), cell("<t[hd]>(.*?)</t[hd]>");
  for (std::sregex_iterator r(table.begin(), table.end(), row), stop; r != stop; ++r) {
    const std::string text = (*r)[1];
    rows.emplace_back();
    for (std::sregex_iterator c(text.begin(), text.end(), cell); c != stop; ++c)
      rows.back().push_back((*c)[1]);
  }
  return rows;
}

json tinyRow(bool dense, double lightScale, int threads) {
  BenchArgs args;
  args.cubes = {5};
  args.threads = {threads};
  args.dense = dense;
  args.lightScale = lightScale;
  args.compare = false;  // no Monte Carlo, no reference grid: fast
  return runBuildRow(args);
}

json tinyRun() {
  json rows = json::array();
  for (auto [dense, lightScale] : {std::pair{false, 1.0}, {false, 0.2}, {true, 1.0}})
    for (int threads : {1, 2}) rows.push_back(tinyRow(dense, lightScale, threads));
  return rows;
}

TEST(BuildReport, TheCheckerCatchesBrokenHtml) {
  EXPECT_TRUE(wellFormed("<p>a &amp; <b>b</b><br></p><svg><circle r='1'/></svg>"));
  EXPECT_FALSE(wellFormed("<p><b>crossed</p></b>"));
  EXPECT_FALSE(wellFormed("<table><tr><td>open</td></table>"));
  EXPECT_FALSE(wellFormed("<p>a & b</p>"));
  EXPECT_FALSE(wellFormed("<p>1 < 2</p>"));
}

TEST(BuildReport, TinyRunGivesTheSummaryTableWithOneRowPerScene) {
  const json rows = tinyRun();
  const json result = buildBenchResult(rows, json::array(), {1, 2}, 1);
  const std::string html = buildReportHtml(result);
  EXPECT_TRUE(wellFormed(html));

  const auto summary = tableCells(html, "summary");
  ASSERT_EQ(summary.size(), 4u);  // header + sparse, sparse light 0.2, dense
  const std::vector<std::string> columns{"N (sparse/dense)",
                                         "faces",
                                         "build s, 1 thread",
                                         "build s, 2 threads",
                                         "ordering s",
                                         "cube s",
                                         "casting + merging s",
                                         "illumination s",
                                         "triangulation s",
                                         "peak MiB",
                                         "vertices"};
  EXPECT_EQ(summary[0], columns);
  EXPECT_EQ(buildSummaryColumns(json{1, 2}), columns);
  const std::vector<std::string> labels{"sparse 5", "sparse 5, light ×0.2", "dense 5"};
  for (size_t i = 1; i < summary.size(); ++i) {
    ASSERT_EQ(summary[i].size(), columns.size());
    EXPECT_EQ(summary[i][0], labels[i - 1]);
    const json& row = rows[2 * (i - 1)];  // its 1-thread row
    EXPECT_EQ(summary[i][1], std::to_string(row["faces"].get<size_t>()));
    EXPECT_EQ(summary[i].back(), std::to_string(row["vertices"].get<size_t>()));
    EXPECT_GT(std::stod(summary[i][9]), 0.0) << "peak MiB";
  }
  EXPECT_EQ(rows[4]["faces"], 6 * 5 + 6);  // dense: six faces per box and the room

  // Speed-up: one row per scene, every step; memory: one row per scene.
  ASSERT_EQ(result["speedup"].size(), 3u);
  for (const json& entry : result["speedup"])
    for (const std::string& step : buildStepKeys())
      EXPECT_TRUE(entry["speedup"].contains(step)) << step;
  const auto speedup = tableCells(html, "speedup");
  ASSERT_EQ(speedup.size(), 4u);
  EXPECT_EQ(speedup[0].size(), 2 + buildStepKeys().size() + 1);  // + build + mesh CPU s
  EXPECT_EQ(speedup[1].size(), speedup[0].size());
  EXPECT_EQ(tableCells(html, "memory").size(), 4u);
  EXPECT_NE(html.find("Build + mesh time vs N"), std::string::npos);
  EXPECT_GE(std::count(html.begin(), html.end(), '\n'), 10);
}

TEST(BuildReport, AFailedBuildIsShownAsFailed) {
  json rows = tinyRun();
  rows.erase(5);  // the dense scene at 2 threads
  const json failures = {{{"scene", "dense"}, {"cubes", 5}, {"light_scale", 1.0}, {"threads", 2}}};
  const json result = buildBenchResult(rows, failures, {1, 2}, 1);
  const std::string html = buildReportHtml(result);
  EXPECT_TRUE(wellFormed(html));
  const auto summary = tableCells(html, "summary");
  ASSERT_EQ(summary.size(), 4u);
  EXPECT_EQ(summary[3][3], "failed");
  EXPECT_NE(summary[2][3], "failed");
  EXPECT_EQ(result["speedup"].size(), 2u);
  EXPECT_NE(html.find("Failed builds"), std::string::npos);
}

TEST(BuildSummary, GrowthExponentIsTheLogLogSlope) {
  auto row = [](int cubes, double faces, double seconds) {
    return json{{"scene", "dense"}, {"cubes", cubes}, {"light_scale", 1.0},
                {"threads", 1},     {"faces", faces}, {"seconds", {{"build_and_mesh", seconds}}}};
  };
  const json growth = buildGrowth(json{row(300, 200, 4), row(150, 100, 1)});
  ASSERT_EQ(growth.size(), 1u);
  const json& points = growth[0]["points"];
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0]["cubes"], 150);
  EXPECT_TRUE(points[0]["exponent"].is_null());
  EXPECT_NEAR(points[1]["exponent"].get<double>(), 2.0, 1e-12);
}

}  // namespace
}  // namespace penumbra::bench
