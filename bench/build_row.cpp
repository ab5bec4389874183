// `penumbra-bench build-row` (hidden; `penumbra-bench build` runs it once per row in a
// child process): one generated scene built at one thread count — the counters, the
// time per step, this process's peak memory (the row's own) and, unless --no-compare,
// the Monte Carlo cost for 1% RMS on the same penumbra vertices and the interpolation
// error against the exact reference grid with the same vertex count.
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "bench/bench_args.h"
#include "bench/lib/mesh_sampling.h"
#include "bench/lib/sample_points.h"
#include "core/engine/engine.h"
#include "core/engine/seconds_since.h"
#include "core/reference/exact_irradiance.h"
#include "core/reference/grid_mesh.h"
#include "core/reference/monte_carlo.h"
#include "protocol/build_stats_json.h"
#include "scenegen/cubes_scene.h"
#include "scenegen/dense_scene.h"
#include "scenegen/model_scene.h"

namespace penumbra::bench {

namespace {

using Clock = std::chrono::steady_clock;

// CPU seconds (user + system) of this process so far: on a shared machine the
// wall clock measures the neighbours too.
double cpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// Peak resident memory of this process so far, in MiB: the row's own peak, since the
// row is the only scene this process builds.
double peakMemoryMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // KiB on Linux
}

struct MonteCarloCost {
  int samples = 0;   // stratified samples per light and vertex for 1% RMS
  double rms = NAN;  // the RMS relative error reached
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

// The penumbra vertices of the built mesh (position, normal, exact value).
struct PenumbraVertices {
  std::vector<Vec3> positions, normals;
  std::vector<double> values;
};

PenumbraVertices penumbraVertices(const Engine& engine) {
  PenumbraVertices out;
  for (const Engine::Receiver& r : engine.receivers())
    for (VertexId v : r.tree.vertices())
      if (const VertexIrradiance value = engine.value(r, v);
          value.lightClass == LightClass::Penumbra && value.irradiance.x > 0) {
        out.positions.push_back(r.frame.to3D(r.tree.position(v)));
        out.normals.push_back(r.frame.normal);
        out.values.push_back(value.irradiance.x);
      }
  return out;
}

// The Monte Carlo estimator's cost for 1% RMS on a seeded subset of `--points` penumbra
// vertices, scaled to all of them; on one thread, as the engine's figures before --threads were.
nlohmann::json monteCarloJson(const Scene& scene, const PenumbraVertices& all, double buildSeconds,
                              const BenchArgs& args) {
  const size_t stride = std::max<size_t>(1, all.positions.size() / args.points);
  PenumbraVertices subset;
  for (size_t i = 0; i < all.positions.size(); i += stride) {
    subset.positions.push_back(all.positions[i]);
    subset.normals.push_back(all.normals[i]);
    subset.values.push_back(all.values[i]);
  }
  MonteCarloCost mc;
  {
    const tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
    mc = monteCarloCost(scene, subset.positions, subset.normals, subset.values, args);
  }
  const double mcSeconds = mc.secondsPerVertex * double(all.positions.size());
  return {{"vertices_sampled", subset.positions.size()},
          {"samples_for_1pct_rms", mc.samples},
          {"rms_relative_error", mc.rms},
          {"seconds_per_vertex", mc.secondsPerVertex},
          {"seconds_all_penumbra_vertices", mcSeconds},
          {"over_build", mcSeconds / buildSeconds}};
}

// The DM mesh against the exact reference grid with about as many vertices.
nlohmann::json meshQualityJson(const Scene& scene, const Mesh& mesh, const BenchArgs& args) {
  const std::vector<SurfacePoint> points = sampleReceivingPoints(scene, args.points, args.seed);
  const ExactReference reference(scene);
  std::vector<double> exact;
  for (const SurfacePoint& p : points)
    exact.push_back(reference.evaluate(p.position, p.normal).irradiance.x);
  // (N+1)² vertices per quad face: pick N for the DM mesh's vertex count.
  const double perFace =
      double(mesh.vertexCount()) / double(std::max<size_t>(1, mesh.receivers.size()));
  const int grid = std::max(1, int(std::lround(std::sqrt(perFace) - 1)));
  const Mesh gridMesh = referenceGridMesh(scene, grid);
  const InterpolationError dm = interpolationError(mesh, points, exact);
  const InterpolationError onGrid = interpolationError(gridMesh, points, exact);
  const double ratio = onGrid.meanRelative > 0 ? dm.meanRelative / onGrid.meanRelative : NAN;
  return {{"points", points.size()},
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

// The row's counters: the build stats (protocol/build_stats_json.h) one level flat, as the
// table and the report read them: "vertices": {"total", "lit", …} becomes "vertices",
// "lit_vertices", …; the row's "seconds" are its own.
nlohmann::json flatCounters(const nlohmann::json& stats) {
  nlohmann::json out;
  for (const auto& [key, value] : stats.items()) {
    if (key == "seconds") continue;
    if (!value.is_object()) {
      out[key] = value;
      continue;
    }
    for (const auto& [part, number] : value.items())
      out[part == "total" ? key : part + "_" + key] = number;
  }
  return out;
}

}  // namespace

nlohmann::json runBuildRow(const BenchArgs& args) {
  if (args.cubes.size() != 1 || args.threads.size() != 1)
    throw std::invalid_argument("build-row takes one --cubes N and one --threads T");
  if (args.models.size() > 1 || args.triangles.size() != 1)
    throw std::invalid_argument("build-row takes at most one --model NAME and one --triangles N");
  int cubes = args.cubes.front();
  const int threads = args.threads.front();
  CubesSceneOptions options;
  options.cubes = cubes;
  options.seed = args.seed;
  options.lightScale = args.lightScale;
  std::string sceneName = args.dense ? "dense" : "sparse";
  Scene scene;
  if (!args.models.empty()) {
    const ModelSceneOptions model{.kind = *modelKindFromName(args.models.front()),
                                  .triangles = args.triangles.front(),
                                  .rest = args.rest,
                                  .seed = args.seed};
    scene = makeModelScene(model);
    cubes = model.triangles > 0 ? model.triangles : defaultModelTriangles(model.kind);
    sceneName = args.models.front() + (args.rest ? "-rest" : "");
  } else {
    scene =
        args.dense ? makeDenseScene({.boxes = cubes, .seed = args.seed}) : makeCubesScene(options);
  }
  // The model's (or boxes') faces: all but the room's static quads.
  size_t modelFaces = 0;
  for (const Object& object : scene.objects())
    if (!object.isStatic) modelFaces += object.faces.size();

  const auto start = Clock::now();
  const double cpuStart = cpuSeconds();
  EngineSettings settings;
  settings.threads = threads;
  settings.silhouetteLinesOnly = !args.allLines;
  settings.closedObjectsAsOne = !args.allLines && !args.faceByFace;
  settings.umbraCulling = args.umbraCulling;
  Engine engine(scene, settings);
  // The display mesh as a server session holds it: the engine's chunks, shared, not copied.
  const auto meshStart = Clock::now();
  size_t meshVertices = 0, meshTriangles = 0;
  for (const Engine::ReceiverChunks& r : engine.meshChunks(engine.receiverFaces()))
    for (const Engine::MeshChunk& chunk : r.chunks) {
      meshVertices += chunk.mesh->positions.size();
      meshTriangles += chunk.mesh->triangles.size();
    }
  const double triangulationSeconds = secondsSince(meshStart);
  const double buildSeconds = secondsSince(start);
  const double buildCpuSeconds = cpuSeconds() - cpuStart;
  const double peakMiB = peakMemoryMiB();  // before the comparisons below allocate theirs
  // One flat copy of it on top, as Engine::mesh() returns and `penumbra build` writes.
  const Mesh mesh = engine.mesh();
  const double flatPeakMiB = peakMemoryMiB();
  BuildStats stats = engine.stats();
  stats.seconds.triangulation = triangulationSeconds;  // mesh() above timed only its copy
  const nlohmann::json statsJson = protocol::buildStatsToJson(stats);

  const bool fixedLight = args.dense || !args.models.empty();
  nlohmann::json row = {{"scene", sceneName},
                        {"cubes", cubes},
                        {"threads", threads},
                        {"light_scale", fixedLight ? 1.0 : args.lightScale}};
  row.update(flatCounters(statsJson));
  row["mesh_vertices"] = meshVertices;
  row["display_triangles"] = meshTriangles;
  row["object_faces"] = modelFaces;
  row["seconds"] = statsJson["seconds"];  // the steps, and the whole build as measured here:
  row["seconds"]["build_and_mesh"] = buildSeconds;
  row["seconds"]["build_and_mesh_cpu"] = buildCpuSeconds;
  row["peak_memory_mib"] = peakMiB;
  row["peak_with_flat_mesh_mib"] = flatPeakMiB;
  row["kb_per_face"] = stats.faces ? peakMiB * 1024.0 / double(stats.faces) : 0.0;
  const PenumbraVertices penumbra = penumbraVertices(engine);
  row["monte_carlo"] = args.compare ? monteCarloJson(scene, penumbra, buildSeconds, args) : nullptr;
  row["mesh_quality"] =
      args.compare && cubes <= args.qualityMaxCubes ? meshQualityJson(scene, mesh, args) : nullptr;
  return row;
}

}  // namespace penumbra::bench
