// `penumbra-microfacet-bench`: direct light on a glossy floor by the DM's visible light pieces
// against shadow rays over the whole light (issue 13, step 5). The options, the measured
// numbers, and the report writer (microfacet_outputs.cpp). Plain values; one thread.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench/lib/image_error.h"

namespace penumbra::bench {

struct MicrofacetBenchArgs {
  int width = 320, height = 240;
  std::vector<int> dmSamples{1, 4, 16, 64, 256};
  std::vector<int> srSamples{1, 4, 16, 64, 256, 1024};
  int referenceSamples = 4096;  // per image; the reference is the mean of two such images
  double roughness = 0.3;
  // The floor's BSDF: single scattering by default, whose eval is exact (no eval noise in either
  // estimator); --scattering multiple: the walk's one-sample eval (README "Benchmarks").
  bool singleScattering = true;
  int threads = 1;           // the ladders (both estimators)
  int referenceThreads = 0;  // the reference images; 0 = every core
  double minSeconds = 0.3;   // each rung is repeated (new seeds) until this much time is spent
  int imageSamples = 4;      // the rung whose images go into the report
  uint64_t seed = 1;
  std::string outDir = "microfacet-bench";
};

// One estimator's ladder: samples, mean wall seconds per image, relative RMS (reference noise
// removed); the same with CPU seconds; the RMS before the removal.
struct Ladder {
  std::string name;
  std::vector<LadderPoint> points, cpuPoints;
  std::vector<double> rawRms;
  std::vector<int> repeats;
};

// Throws std::invalid_argument naming the bad option.
MicrofacetBenchArgs parseMicrofacetArgs(int argc, char** argv);

}  // namespace penumbra::bench

namespace penumbra::bench {

// The images of the report: linear RGB per pixel; microfacet pixels (mask) from the estimators,
// the rest (`base`: the diffuse box lit by the DM mesh, black background) shared by all.
struct BenchImages {
  int width = 0, height = 0;
  std::vector<uint8_t> mask;
  std::vector<float> base, reference, dm, shadowRays;
  int samples = 0;  // of dm and shadowRays
};

// Writes into args.outDir: dm.png, shadow_rays.png, reference.png, the error heat maps, the
// side-by-side comparison.png, comparison_middle.png (the middle half of each picture),
// error_vs_time.svg, report.html and microfacet.json. Throws on a write failure.
void writeMicrofacetReport(const MicrofacetBenchArgs& args, const BenchImages& images,
                           const Ladder& dm, const Ladder& shadowRays,
                           const nlohmann::json& numbers, const std::string& markdown);

}  // namespace penumbra::bench
