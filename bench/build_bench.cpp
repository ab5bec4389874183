// `penumbra-bench build`: the full discontinuity-mesh build on generated 'N cubes
// in a room' scenes at two light sizes (--dense: 'N boxes floating in a room', one
// light) — times split by step and the counters — against (a) what the Monte Carlo
// estimator needs for 1% RMS relative error on the same penumbra vertices and (b)
// the exact reference grid with the same vertex count (mean relative interpolation
// error at random points). One thread.
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "bench/bench_args.h"
#include "bench/lib/cubes_scene.h"
#include "bench/lib/dense_scene.h"
#include "bench/lib/mesh_sampling.h"
#include "bench/lib/sample_points.h"
#include "core/engine/engine.h"
#include "core/reference/exact_irradiance.h"
#include "core/reference/grid_mesh.h"
#include "core/reference/monte_carlo.h"

namespace penumbra::bench {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// CPU seconds (user + system) of this process so far: on a shared machine the
// wall clock measures the neighbours too.
double cpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// Peak resident memory of this process so far (all rows up to this one), in MiB.
double peakMemoryMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // KiB on Linux
}

struct MonteCarloCost {
  int samples = 0;          // stratified samples per light and vertex for 1% RMS
  double rms = NAN;         // the RMS relative error reached
  double secondsPerVertex = NAN;
};

// Doubles the samples until the RMS relative error over the given points is 1%.
MonteCarloCost monteCarloCost(const Scene& scene, const std::vector<Vec3>& positions,
                              const std::vector<Vec3>& normals, const std::vector<double>& truth,
                              const BenchArgs& args) {
  MonteCarloCost cost;
  if (positions.empty()) return cost;
  const MonteCarloEstimator estimator(scene);
  for (int n = 64; n <= args.maxSamples; n *= 2) {
    MonteCarloOptions options;
    options.samplesPerLight = n;
    options.seed = args.seed;
    options.stratified = true;
    const auto start = Clock::now();
    const auto estimates = estimator.estimateMany(positions, normals, options);
    cost.secondsPerVertex = secondsSince(start) / double(positions.size());
    double sum = 0;
    for (size_t i = 0; i < truth.size(); ++i) {
      const double relative = (estimates[i].irradiance.x - truth[i]) / truth[i];
      sum += relative * relative;
    }
    cost.rms = std::sqrt(sum / double(truth.size()));
    cost.samples = n;
    if (cost.rms <= 0.01) break;
  }
  return cost;
}

struct InterpolationError {
  double meanRelative = 0;  // mean of |mesh − exact| / exact over points with exact > 0
  double relativeL1 = 0;    // Σ|mesh − exact| / Σ exact over all points
  double darkLeak = 0;      // share of points with exact = 0 where the mesh is not 0
};

InterpolationError interpolationError(const Mesh& mesh, const std::vector<SurfacePoint>& points,
                                      const std::vector<double>& exact) {
  const MeshInterpolator interpolator(mesh);
  InterpolationError out;
  double error = 0, total = 0, relative = 0;
  size_t lit = 0, dark = 0, leaks = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const auto value = interpolator.at(points[i].face, points[i].position);
    if (!value) continue;
    const double difference = std::abs(value->x - exact[i]);
    error += difference;
    total += exact[i];
    if (exact[i] > 0) {
      relative += difference / exact[i];
      ++lit;
    } else {
      ++dark;
      leaks += value->x > 0;
    }
  }
  out.meanRelative = lit ? relative / double(lit) : 0;
  out.relativeL1 = total > 0 ? error / total : 0;
  out.darkLeak = dark ? double(leaks) / double(dark) : 0;
  return out;
}

}  // namespace

nlohmann::json runBuildBench(const BenchArgs& args) {
  nlohmann::json rows = nlohmann::json::array();
  std::printf("%6s %5s %6s %8s %8s %7s %8s %9s %6s | %9s %9s %8s %8s | %9s %9s %8s\n", "cubes", "light",
              "faces", "pairs", "shadows", "nodes", "vertices", "penumbra", "cmp/v", "build s", "cpu s",
              "cast %", "illum %", "MC s", "MC/build", "DM/grid");
  for (int cubes : args.cubes) {
    for (double lightScale : {1.0, 0.2}) {
      // Dense rooms have one light size: one row per N.
      if (args.dense && lightScale != 1.0) continue;
      CubesSceneOptions options;
      options.cubes = cubes;
      options.seed = args.seed;
      options.lightScale = lightScale;
      const Scene scene =
          args.dense ? makeDenseScene({.boxes = cubes, .seed = args.seed}) : makeCubesScene(options);

      const auto start = Clock::now();
      const double cpuStart = cpuSeconds();
      EngineSettings settings;
      settings.threads = args.threads;
      Engine engine(scene, settings);
      const Mesh mesh = engine.mesh();
      const double buildSeconds = secondsSince(start);
      const double buildCpuSeconds = cpuSeconds() - cpuStart;
      const double peakMiB = peakMemoryMiB();
      const BuildStats& stats = engine.stats();

      // The penumbra vertices, and a seeded subset for the Monte Carlo estimate.
      std::vector<Vec3> positions, normals;
      std::vector<double> truth;
      for (const Engine::Receiver& r : engine.receivers())
        for (VertexId v : r.tree.vertices())
          if (r.values[v.index].lightClass == LightClass::Penumbra && r.values[v.index].irradiance.x > 0) {
            positions.push_back(r.frame.to3D(r.tree.position(v)));
            normals.push_back(r.frame.normal);
            truth.push_back(r.values[v.index].irradiance.x);
          }
      const size_t penumbraVertices = positions.size();
      const size_t stride = std::max<size_t>(1, positions.size() / args.points);
      std::vector<Vec3> mcPositions, mcNormals;
      std::vector<double> mcTruth;
      for (size_t i = 0; i < positions.size(); i += stride) {
        mcPositions.push_back(positions[i]);
        mcNormals.push_back(normals[i]);
        mcTruth.push_back(truth[i]);
      }
      MonteCarloCost mc;
      {  // on one thread, as the engine's figures before --threads were
        const tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
        mc = monteCarloCost(scene, mcPositions, mcNormals, mcTruth, args);
      }
      const double mcSeconds = mc.secondsPerVertex * double(penumbraVertices);

      // Mesh quality against the reference grid with about as many vertices.
      nlohmann::json quality = nullptr;
      double ratio = NAN;
      if (cubes <= args.qualityMaxCubes) {
        const std::vector<SurfacePoint> points = sampleReceivingPoints(scene, args.points, args.seed);
        const ExactReference reference(scene);
        std::vector<double> exact;
        for (const SurfacePoint& p : points) exact.push_back(reference.evaluate(p.position, p.normal).irradiance.x);
        // (N+1)² vertices per quad face: pick N for the DM mesh's vertex count.
        const double perFace = double(mesh.vertexCount()) / double(std::max<size_t>(1, mesh.receivers.size()));
        const int grid = std::max(1, int(std::lround(std::sqrt(perFace) - 1)));
        const Mesh gridMesh = referenceGridMesh(scene, grid);
        const InterpolationError dm = interpolationError(mesh, points, exact);
        const InterpolationError onGrid = interpolationError(gridMesh, points, exact);
        ratio = onGrid.meanRelative > 0 ? dm.meanRelative / onGrid.meanRelative : NAN;
        quality = {{"points", points.size()},
                   {"dm_vertices", mesh.vertexCount()},
                   {"grid", grid},
                   {"grid_vertices", gridMesh.vertexCount()},
                   {"dm_mean_relative_error", dm.meanRelative},
                   {"grid_mean_relative_error", onGrid.meanRelative},
                   {"dm_over_grid", ratio},
                   {"dm_relative_l1_error", dm.relativeL1},
                   {"grid_relative_l1_error", onGrid.relativeL1},
                   {"dm_dark_points_lit", dm.darkLeak},
                   {"grid_dark_points_lit", onGrid.darkLeak}};
      }
      const BuildTimings& t = stats.seconds;
      std::printf("%6d %5.1f %6zu %8zu %8zu %7zu %8zu %9zu %6.2f | %9.3f %9.3f %7.0f%% %7.0f%% | %9.1f %9.0f %8.3f\n",
                  cubes, lightScale, stats.faces, stats.candidatePairs, stats.pairsWithShadow,
                  stats.treeNodes, stats.vertices, penumbraVertices, stats.comparisonsPerVertex(),
                  buildSeconds, buildCpuSeconds, 100 * t.castingAndMerging / t.total(),
                  100 * t.illumination / t.total(),
                  mcSeconds, mcSeconds / buildSeconds, ratio);
      std::fflush(stdout);
      rows.push_back({{"cubes", cubes},
                      {"threads", args.threads},
                      {"light_scale", lightScale},
                      {"faces", stats.faces},
                      {"candidate_pairs", stats.candidatePairs},
                      {"pairs_with_shadow", stats.pairsWithShadow},
                      {"tiles", stats.tiles},
                      {"tree_nodes", stats.treeNodes},
                      {"cells", stats.cells},
                      {"vertices", stats.vertices},
                      {"lit_vertices", stats.litVertices},
                      {"penumbra_vertices", stats.penumbraVertices},
                      {"umbra_vertices", stats.umbraVertices},
                      {"comparisons_per_vertex", stats.comparisonsPerVertex()},
                      {"seconds", {{"ordering", t.ordering},
                                   {"cube", t.cube},
                                   {"casting_and_merging", t.castingAndMerging},
                                   {"illumination", t.illumination},
                                   {"triangulation", t.triangulation},
                                   {"build_and_mesh", buildSeconds},
                                   {"build_and_mesh_cpu", buildCpuSeconds}}},
                      {"peak_memory_mib_so_far", peakMiB},
                      {"monte_carlo", {{"vertices_sampled", mcPositions.size()},
                                       {"samples_for_1pct_rms", mc.samples},
                                       {"rms_relative_error", mc.rms},
                                       {"seconds_per_vertex", mc.secondsPerVertex},
                                       {"seconds_all_penumbra_vertices", mcSeconds},
                                       {"over_build", mcSeconds / buildSeconds}}},
                      {"mesh_quality", quality}});
    }
  }
  return {{"benchmark", "build"}, {"scenes", args.dense ? "dense" : "cubes"}, {"seed", args.seed},
          {"rows", rows}};
}

}  // namespace penumbra::bench
