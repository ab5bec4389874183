// The self-contained HTML report of `penumbra-bench build`: the summary table of issue
// 11's closing note, build time vs N (log–log) for sparse and dense rooms, the time per
// step, the speed-up per step between thread counts, peak memory and vertices; inline
// SVG only (no scripts, no external resources). Pure function of the JSON; thread-safe.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace penumbra::bench {

// `result` is what buildBenchResult returns (bench/report/build_summary.h).
std::string buildReportHtml(const nlohmann::json& result);

// The columns of the summary table (issue 11's closing note): N (sparse/dense), faces,
// build s at each of `threads`, the time per step at the first count, peak MiB, vertices.
std::vector<std::string> buildSummaryColumns(const nlohmann::json& threads);

}  // namespace penumbra::bench
