// Options shared by the `penumbra-bench` drivers, parsed once from argv.
// Plain value; not shared between threads.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace penumbra::bench {

struct BenchArgs {
  std::vector<int> cubes{15, 150, 1500};
  uint64_t seed = 1;
  double lightScale = 1.0;
  size_t points = 2000;
  int maxSamples = 1 << 16;
  // build: engine threads per row (EngineSettings::threads; 0 = every core); each scene is
  // built once per count.
  std::vector<int> threads{1};
  int qualityMaxCubes = 150;  // mesh-quality comparison only up to this scene size
  std::string jsonOut;        // empty: no JSON file
  bool dense = false;         // build, edits: dense rooms (makeDenseScene) instead of cubes rooms
  // build: --dense-cubes N,...: dense rooms in the same run as the cubes rooms of --cubes
  // (then --cubes only when given). build-row: --no-compare skips Monte Carlo and mesh quality.
  std::vector<int> denseCubes;
  bool compare = true;
  // build, build-row: --model NAME,... (scenegen/model_scene.h: teapot, torus-knot, blob,
  // bowl, scan, furnished) at --triangles N,... (0: the model's default), floating or with
  // --rest on the floor: one row per model, count and thread count (then --cubes only when
  // given). build-row takes one model and one count.
  std::vector<std::string> models;
  std::vector<int> triangles{0};
  bool rest = false;
  // build, build-row: --all-lines casts every VE/EV line of closed convex objects
  // of every face (EngineSettings::silhouetteLinesOnly and closedObjectsAsOne false), to
  // compare with the default; --face-by-face casts closed convex objects face by face with
  // silhouette lines only (closedObjectsAsOne false).
  bool allLines = false;
  bool faceByFace = false;
  // build, build-row, edits: --no-umbra-culling turns EngineSettings::umbraCulling off.
  bool umbraCulling = true;
  // edits: --cubes given (else 150,1500,5000), --frames (drag frames, 0 = by size),
  // --html OUT, --write-scripts DIR --scene FILE (write that scene's scripts only).
  // --rebuild-every K: time the full rebuild on the first frame, every K-th and
  // the last (0 = by size: every frame up to 2000 cubes, else every 10th).
  bool cubesGiven = false;
  int frames = 0;
  int rebuildEvery = 0;
  std::string htmlOut, writeScripts, scenePath;
};

// Throws std::invalid_argument naming the bad option.
BenchArgs parseBenchArgs(int argc, char** argv, int first);

nlohmann::json runReferenceBench(const BenchArgs& args);
nlohmann::json runBuildBench(const BenchArgs& args);
// The hidden `build-row` mode: one scene (--cubes N, [--dense], --light-scale, --threads T)
// built in this process, so its peak memory is its own (bench/build_row.cpp).
nlohmann::json runBuildRow(const BenchArgs& args);
nlohmann::json runEditsBench(const BenchArgs& args);

}  // namespace penumbra::bench
