#include <sys/resource.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <map>
#include <optional>
#include <string>

#include "cli/commands.h"
#include "cli/progress_bar.h"
#include "core/engine/engine.h"
#include "core/gi/sensor_gi.h"
#include "core/raycast/ray_scene.h"
#include "core/util/parallel.h"
#include "interchange/dm_edges.h"
#include "interchange/glb_export.h"
#include "protocol/build_stats_json.h"
#include "protocol/mesh_json.h"
#include "protocol/scene_json.h"

namespace penumbra::cli {

namespace {

// Peak resident memory of this process so far, in MiB.
double peakMemoryMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

// The display mesh's receivers, vertices and triangles per scene object (by id): where a
// scene's triangles go (a model's small faces against the room's floor under its shadow).
nlohmann::json meshByObject(const Scene& scene, const Mesh& mesh) {
  std::map<std::string, std::array<size_t, 3>> counts;  // receivers, vertices, triangles
  for (const ReceiverMesh& r : mesh.receivers) {
    auto& [receivers, vertices, triangles] = counts[scene.object(r.face.object).id];
    ++receivers, vertices += r.positions.size(), triangles += r.triangles.size();
  }
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [id, c] : counts) out[id] = {{"receivers", c[0]}, {"vertices", c[1]}, {"triangles", c[2]}};
  return out;
}

// The build stats (protocol/build_stats_json.h) with the written mesh, its refinement's test
// points (meshing: the engine's last display-mesh update) and this process's peak.
nlohmann::json statsJson(const Scene& scene, const BuildStats& s, const Mesh& mesh, const MeshMemoCounters& meshing) {
  nlohmann::json out = protocol::buildStatsToJson(s);
  out["mesh"] = {{"vertices", mesh.vertexCount()},
                 {"triangles", mesh.triangleCount()},
                 {"tolerance", mesh.tolerance},
                 {"capped_cells", mesh.cappedCells},
                 // Where triangulation's time goes: each test point is an exact value.
                 {"test_points", meshing.testPoints},
                 {"test_points_kept", meshing.testPointsKept},
                 {"by_object", meshByObject(scene, mesh)}};
  out["peak_memory_mib"] = peakMemoryMiB();
  return out;
}

// --indirect: every vertex's indirect irradiance (sensors of --sensor-size², core/gi), timed.
std::optional<Mesh> bakedIndirect(const Args& args, const Scene& scene, const Mesh& mesh, int threads) {
  if (!args.flag("indirect")) {
    if (args.option("sensor-size") || args.option("bounces")) throw UsageError("--sensor-size and --bounces need --indirect");
    return std::nullopt;
  }
  const int sensorSize = args.intOption("sensor-size", 8, 1, 64);
  const int bounces = args.intOption("bounces", 1, 1, 4);
  const auto start = std::chrono::steady_clock::now();
  const RayScene rays(scene);
  Mesh indirect = gi::vertexIndirect(scene, rays, mesh, sensorSize, bounces, Parallel(threads));
  std::fprintf(stderr, "indirect light: %zu vertices, sensors of %d², %d bounce(s), %.3f s\n", mesh.vertexCount(),
               sensorSize, bounces, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return indirect;
}

}  // namespace

int runBuild(const Args& args) {
  args.allowOnly({"out", "grid", "color-scale", "threads", "sensor-size", "bounces", "mesh-tolerance"});
  const std::string scenePath = args.positional(0, "SCENE");
  const auto out = args.option("out");
  if (!out) throw UsageError("build needs --out MESH");
  EngineSettings settings;
  settings.overlapGrid = args.intOption("grid", 0, 0, 256);
  settings.threads = args.intOption("threads", 0, 0, 1024);
  settings.meshTolerance = meshToleranceOption(args);
  const Scene scene = protocol::loadSceneFile(scenePath);

  BuildBars bars;
  Engine engine(scene, settings, bars.progress());
  bars.finish();
  ProgressBar triangulation("triangulation");
  const Mesh mesh = engine.mesh([&](const char*, size_t done, size_t total) { triangulation.update(done, total); });
  triangulation.finish();
  if (std::filesystem::path(*out).extension() == ".glb") {  // glTF binary (interchange/glb_export.h)
    interchange::GlbOptions glb;
    glb.colorScale = args.doubleOption("color-scale", 0);
    if (args.flag("edges")) glb.edges = interchange::dmEdges(engine);
    const std::optional<Mesh> indirect = bakedIndirect(args, engine.scene(), mesh, settings.threads);
    if (indirect) glb.indirect = &*indirect;
    const interchange::GlbFile file = interchange::saveMeshGlb(engine.scene(), mesh, *out, glb);
    std::fprintf(stderr, "GLB COLOR_0 = min(1, %.9g x radiance with %s (W m^-2 sr^-1)); exact values in _RADIANCE, "
                 "_IRRADIANCE\n", file.colorScale, indirect ? "the indirect light" : "the ambient fill");
  } else {
    protocol::saveMeshFile(engine.scene(), mesh, std::filesystem::path(scenePath).filename().string(), *out);
  }

  const BuildStats& stats = engine.stats();
  if (args.flag("stats")) {
    std::printf("%s\n", statsJson(engine.scene(), stats, mesh, engine.lastMeshCounters()).dump(2).c_str());
  } else {
    char bound[128];  // tolerance 0 claims no bound (cells not refined)
    if (mesh.tolerance > 0)
      std::snprintf(bound, sizeof bound, "interpolation within %g of the local unshadowed light (%zu cells capped)",
                    mesh.tolerance, mesh.cappedCells);
    else
      std::snprintf(bound, sizeof bound, "cells not refined (no interpolation bound)");
    std::printf("wrote %s: %zu receivers, %zu vertices, %zu triangles, %s (%.3f s)\n", out->c_str(),
                mesh.receivers.size(), mesh.vertexCount(), mesh.triangleCount(), bound, stats.seconds.total());
  }
  return 0;
}

}  // namespace penumbra::cli
