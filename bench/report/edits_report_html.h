// The self-contained HTML report of `penumbra-bench edits`: inline SVG plots (no
// scripts, no external resources) and the JSON of the same numbers. Pure
// function of the benchmark's JSON; thread-safe.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace penumbra::bench {

// `result` is what runEditsBench returns (see bench/edits_bench.cpp).
std::string editsReportHtml(const nlohmann::json& result);

}  // namespace penumbra::bench
