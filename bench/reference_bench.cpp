// `penumbra-bench reference`: time of the exact reference per point, and what the
// Monte Carlo estimator needs (samples, time) to reach 1% RMS relative error on
// the same penumbra points, on generated 'N cubes in a room' scenes. One thread,
// so the two are compared like for like; results as a table and JSON.
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "bench/bench_args.h"
#include "bench/lib/sample_points.h"
#include "core/engine/seconds_since.h"
#include "core/reference/exact_irradiance.h"
#include "core/reference/monte_carlo.h"
#include "scenegen/cubes_scene.h"

namespace penumbra::bench {

namespace {

}  // namespace

nlohmann::json runReferenceBench(const BenchArgs& args) {
  tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
  nlohmann::json rows = nlohmann::json::array();
  std::printf("%7s %7s %8s %10s %9s %12s %9s %12s %10s\n", "cubes", "faces", "points", "penumbra",
              "ref us/pt", "MC samples", "MC rms", "MC us/pt", "MC / ref");
  for (int cubes : args.cubes) {
    CubesSceneOptions options;
    options.cubes = cubes;
    options.seed = args.seed;
    options.lightScale = args.lightScale;
    const Scene scene = makeCubesScene(options);
    const std::vector<SurfacePoint> points = sampleReceivingPoints(scene, args.points, args.seed);

    const ExactReference reference(scene);
    std::vector<PointIrradiance> exact(points.size());
    const auto start = std::chrono::steady_clock::now();
    for (size_t i = 0; i < points.size(); ++i) exact[i] = reference.evaluate(points[i].position, points[i].normal);
    const double referenceSeconds = secondsSince(start) / double(points.size());

    std::vector<Vec3> positions, normals;
    std::vector<double> truth;
    for (size_t i = 0; i < points.size(); ++i) {
      if (exact[i].lightClass != LightClass::Penumbra || !(exact[i].irradiance.x > 0)) continue;
      positions.push_back(points[i].position);
      normals.push_back(points[i].normal);
      truth.push_back(exact[i].irradiance.x);
    }

    // Doubling the samples until the RMS relative error over the penumbra points is 1%.
    const MonteCarloEstimator estimator(scene);
    int samples = 0;
    double mcSeconds = NAN, rms = NAN;
    for (int n = 64; n <= args.maxSamples && !positions.empty(); n *= 2) {
      MonteCarloOptions mc;
      mc.samplesPerLight = n;
      mc.seed = args.seed;
      mc.stratified = true;
      const auto mcStart = std::chrono::steady_clock::now();
      const auto estimates = estimator.estimateMany(positions, normals, mc);
      const double seconds = secondsSince(mcStart) / double(positions.size());
      double sum = 0;
      for (size_t i = 0; i < truth.size(); ++i) {
        const double relative = (estimates[i].irradiance.x - truth[i]) / truth[i];
        sum += relative * relative;
      }
      rms = std::sqrt(sum / double(truth.size()));
      samples = n;
      mcSeconds = seconds;
      if (rms <= 0.01) break;
    }
    std::printf("%7d %7zu %8zu %10zu %9.2f %12d %8.2f%% %12.1f %10.0f\n", cubes,
                scene.faces().size(), points.size(), positions.size(), 1e6 * referenceSeconds,
                samples, 100 * rms, 1e6 * mcSeconds, mcSeconds / referenceSeconds);
    rows.push_back({{"cubes", cubes},
                    {"faces", scene.faces().size()},
                    {"points", points.size()},
                    {"penumbra_points", positions.size()},
                    {"reference_us_per_point", 1e6 * referenceSeconds},
                    {"mc_samples_for_1pct_rms", samples},
                    {"mc_rms_relative_error", rms},
                    {"mc_us_per_point", 1e6 * mcSeconds}});
  }
  return {{"benchmark", "reference"}, {"seed", args.seed}, {"light_scale", args.lightScale}, {"rows", rows}};
}

}  // namespace penumbra::bench
