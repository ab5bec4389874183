// What `penumbra-bench build` derives from its rows: the speed-up per build step from
// the first --threads count to the others, and how build time grows with N (the log–log
// slope between consecutive sizes). Pure functions of the rows' JSON; thread-safe.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace penumbra::bench {

// The build steps of BuildTimings as named in a row's "seconds", then the whole
// build + mesh (wall).
const std::vector<std::string>& buildStepKeys();
// "ordering", "cube", "casting + merging", ... for reports.
const std::vector<std::string>& buildStepLabels();

// "sparse 150", "sparse 150, light ×0.2", "dense 150" (from "scene", "cubes", "light_scale").
std::string sceneLabel(const nlohmann::json& row);
// "sparse", "sparse, light ×0.2", "dense".
std::string sceneKindLabel(const std::string& scene, double lightScale);

// Per scene (scene, cubes, light_scale) and every thread count after the first in
// `threads`: {"scene", "cubes", "light_scale", "from_threads", "to_threads", "seconds":
// {step: [from, to]}, "cpu_seconds": [from, to] (build + mesh), "speedup": {step: from / to
// (null if to is 0)}}.
nlohmann::json threadSpeedups(const nlohmann::json& rows, const std::vector<int>& threads);

// Per (scene, light_scale, threads), sizes ascending: {"scene", "light_scale", "threads",
// "points": [{"cubes", "faces", "seconds", "exponent"}]} where exponent is
// log(t_i / t_{i-1}) / log(faces_i / faces_{i-1}) (null for the first size).
nlohmann::json buildGrowth(const nlohmann::json& rows);

// The result of `penumbra-bench build`: {"benchmark": "build", "scenes": "cubes" | "dense" |
// "cubes+dense", "seed", "threads", "hardware_threads", "rows", "failures", "speedup", "growth"}.
nlohmann::json buildBenchResult(const nlohmann::json& rows, const nlohmann::json& failures,
                                const std::vector<int>& threads, uint64_t seed);

}  // namespace penumbra::bench
