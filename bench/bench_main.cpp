// `penumbra-bench BENCHMARK [options]`: the benchmark driver. Prints a table,
// and with --json OUT writes the same numbers as JSON.
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/bench_args.h"
#include "scenegen/model_scene.h"

namespace penumbra::bench {

namespace {

// "15,150,1500" → {15, 150, 1500}; throws on an empty list or a value below `least`.
std::vector<int> intList(const std::string& text, int least) {
  std::vector<int> out;
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');) {
    size_t used = 0;
    out.push_back(std::stoi(item, &used));
    if (used != item.size()) throw std::invalid_argument("not a whole number: " + item);
    if (out.back() < least) throw std::invalid_argument("must be >= " + std::to_string(least));
  }
  if (out.empty()) throw std::invalid_argument("empty list");
  return out;
}

}  // namespace

BenchArgs parseBenchArgs(int argc, char** argv, int first) {
  BenchArgs args;
  for (int i = first; i < argc; ++i) {
    const std::string name = argv[i];
    if (name == "--dense" || name == "--no-compare" || name == "--all-lines" || name == "--face-by-face" ||
        name == "--no-umbra-culling" || name == "--rest") {  // no value
      if (name == "--dense") args.dense = true;
      if (name == "--no-compare") args.compare = false;
      if (name == "--all-lines") args.allLines = true;
      if (name == "--face-by-face") args.faceByFace = true;
      if (name == "--no-umbra-culling") args.umbraCulling = false;
      if (name == "--rest") args.rest = true;
      continue;
    }
    if (i + 1 >= argc) throw std::invalid_argument(name + " needs a value");
    const std::string value = argv[++i];
    try {
      if (name == "--cubes") {
        args.cubes = intList(value, 0);
        args.cubesGiven = true;
      } else if (name == "--dense-cubes") {
        args.denseCubes = intList(value, 0);
      } else if (name == "--model") {
        args.models.clear();
        std::stringstream list(value);
        for (std::string item; std::getline(list, item, ',');) {
          if (!modelKindFromName(item)) throw std::invalid_argument("not one of " + modelKindNames());
          args.models.push_back(item);
        }
        if (args.models.empty()) throw std::invalid_argument("empty list");
      } else if (name == "--triangles") {
        args.triangles = intList(value, kMinModelTriangles);
        for (int n : args.triangles)
          if (n > kMaxModelTriangles) throw std::invalid_argument("must be <= " + std::to_string(kMaxModelTriangles));
      } else if (name == "--seed") {
        args.seed = std::stoull(value);
      } else if (name == "--light-scale") {
        args.lightScale = std::stod(value);
      } else if (name == "--points") {
        args.points = std::stoul(value);
      } else if (name == "--max-samples") {
        args.maxSamples = std::stoi(value);
      } else if (name == "--quality-max-cubes") {
        args.qualityMaxCubes = std::stoi(value);
      } else if (name == "--threads") {
        args.threads = intList(value, 0);
      } else if (name == "--frames") {
        args.frames = std::stoi(value);
      } else if (name == "--rebuild-every") {
        args.rebuildEvery = std::stoi(value);
        if (args.rebuildEvery < 0) throw std::invalid_argument("must be >= 0");
      } else if (name == "--html") {
        args.htmlOut = value;
      } else if (name == "--write-scripts") {
        args.writeScripts = value;
      } else if (name == "--scene") {
        args.scenePath = value;
      } else if (name == "--json") {
        args.jsonOut = value;
      } else {
        throw std::invalid_argument("unknown option " + name);
      }
    } catch (const std::logic_error& error) {
      throw std::invalid_argument(name + " '" + value + "': " + error.what());
    }
  }
  return args;
}

}  // namespace penumbra::bench

int main(int argc, char** argv) {
  using namespace penumbra::bench;
  constexpr const char* kUsage =
      "usage: penumbra-bench reference|build|edits [--cubes 15,150,1500] [--seed S] [--light-scale "
      "F]\n"
      "                      [--json OUT]\n"
      "                      build: [--dense-cubes 150,300] [--dense] [--threads 1,2] [--html "
      "OUT]\n"
      "                             [--points K] [--max-samples N] [--quality-max-cubes N]\n"
      "                             [--all-lines] (closed convex objects face by face, every VE/EV line)\n"
      "                             [--face-by-face] (closed convex objects face by face, silhouette lines)\n"
      "                             [--no-umbra-culling] (later shadows split cells in an umbra too)\n"
      "                             [--model teapot|torus-knot|blob|bowl|scan|furnished,...]\n"
      "                             [--triangles N,...] [--rest] (models in the dense room)\n"
      "                      edits: [--dense] [--frames F] [--rebuild-every K] [--html OUT]\n"
      "                             | --write-scripts DIR --scene FILE\n"
      "  reference: exact reference and Monte Carlo cost per point\n"
      "  build:     DM build times per step, counters, peak memory: sparse rooms (--cubes) at "
      "light\n"
      "             scales 1 and 0.2 and dense rooms (--dense-cubes: N boxes floating in 6×3×6 m, "
      "one\n"
      "             light; --dense: --cubes are dense rooms), each at every --threads count "
      "(engine\n"
      "             threads, default 1; 0 = every core) in its own process; at the first count "
      "also the\n"
      "             Monte Carlo cost for 1% RMS on the penumbra vertices and DM vs equal-vertex "
      "grid\n"
      "             error; --html writes the report (time vs N, steps, speed-up, memory)\n"
      "  edits:     edit scripts (drag, move 1/5/10/30% of faces, remove-add, build-up) per frame "
      "vs a\n"
      "             full rebuild, default --cubes 150,1500,5000; --dense: dragging one floating "
      "box\n"
      "             in the dense rooms; --html writes the report\n";
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  try {
    const std::string benchmark = argv[1];
    const BenchArgs args = parseBenchArgs(argc, argv, 2);
    nlohmann::json result;
    if (benchmark == "reference") {
      result = runReferenceBench(args);
    } else if (benchmark == "build") {
      result = runBuildBench(args);
    } else if (benchmark == "build-row") {  // hidden: one row, JSON on stdout (build_bench.cpp)
      std::printf("%s\n", runBuildRow(args).dump().c_str());
      return 0;
    } else if (benchmark == "edits") {
      result = runEditsBench(args);
    } else {
      std::fputs(kUsage, stderr);
      return 2;
    }
    if (!args.jsonOut.empty()) {
      std::ofstream(args.jsonOut) << result.dump(2) << "\n";
      std::printf("wrote %s\n", args.jsonOut.c_str());
    }
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "penumbra-bench: %s\n", error.what());
    return 2;
  }
}
