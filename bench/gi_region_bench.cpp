// `penumbra-gi-region-bench [--scene FILE] [--size N] [--pixels K] [--paths P] [--tolerance T]
// [--sensor-size N] [--threads T] [--seed S] [--json OUT]` (docs/RENDERING.md "Where sensor GI is biased"): the
// sensor GI image's indirect irradiance per region of the view (the room's faces by name, the
// objects' tops, sides and bottoms), against the one-bounce path tracer twice, with the same
// random directions: once taking the direct light at each hit from the display mesh (what the
// sensors see) and once from the exact reference (core/reference: nothing of the DM at all).
// The first pair shows the sensors' own error; the second the bias the display mesh's
// interpolation passes on to bounced light. Seeded; one line per region.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/lib/gi_path_tracer.h"
#include "core/engine/engine.h"
#include "core/gi/sensor_gi.h"
#include "core/gi/view_gbuffer.h"
#include "core/raycast/camera_projection.h"
#include "core/reference/exact_irradiance.h"
#include "protocol/scene_json.h"

using namespace penumbra;
using nlohmann::json;

namespace {

struct Options {
  std::string scene = "scenes/cubes15.scene.json";
  int size = 64, pixels = 40, paths = 20000, threads = 2, sensorSize = gi::GiSettings{}.sensorSize;
  double tolerance = -1;  // < 0: the engine's default
  uint64_t seed = 7;
  std::string jsonOut;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string name = argv[i];
    if (i + 1 >= argc) throw std::invalid_argument(name + " needs a value");
    const std::string value = argv[++i];
    if (name == "--scene") o.scene = value;
    else if (name == "--size") o.size = std::stoi(value);
    else if (name == "--pixels") o.pixels = std::stoi(value);
    else if (name == "--paths") o.paths = std::stoi(value);
    else if (name == "--tolerance") o.tolerance = std::stod(value);
    else if (name == "--sensor-size") o.sensorSize = std::stoi(value);
    else if (name == "--threads") o.threads = std::stoi(value);
    else if (name == "--seed") o.seed = std::stoull(value);
    else if (name == "--json") o.jsonOut = value;
    else throw std::invalid_argument("unknown option " + name);
  }
  return o;
}

// A static object's faces are named by the object; movable objects are pooled by orientation.
std::string regionOf(const Scene& scene, const Face& face) {
  const Object& object = scene.object(face.id.object);
  if (object.isStatic) return object.id;
  const double y = face.plane.normal.y;
  return std::string("objects, ") + (y > 0.9 ? "tops" : y < -0.9 ? "bottoms" : "sides");
}

double brightness(const Vec3& v) { return (v.x + v.y + v.z) / 3; }

struct Sums {
  int pixels = 0;
  double sensors = 0, meshTraced = 0, exactTraced = 0;
  // Per-pixel ratios' sums for the spread of the bias (pixel to pixel and path noise together).
  double sensorsOverExact = 0, sensorsOverExactSquares = 0, meshOverExact = 0, meshOverExactSquares = 0;
};

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
  const Scene scene = protocol::loadSceneFile(o.scene);
  EngineSettings settings;
  settings.threads = o.threads;
  if (o.tolerance >= 0) settings.meshTolerance = o.tolerance;
  Engine engine(scene, settings);
  const Mesh mesh = engine.mesh();
  const RayScene rays(scene);
  const MeshLookup lookup(scene, mesh);
  const ExactReference exact(scene);
  const Parallel parallel(o.threads);
  const Camera camera = scene.camera().value_or(defaultCamera(scene.bounds()));
  const gi::GBuffer view = gi::viewGBuffer(rays, camera, o.size, o.size, parallel);
  gi::GiSettings gi;
  gi.sensorSize = o.sensorSize;
  const gi::IndirectImage image = gi::indirectImage(scene, rays, mesh, view, gi, parallel);

  // Up to --pixels random pixels per region.
  std::map<std::string, std::vector<size_t>> regions;
  for (size_t p = 0; p < view.face.size(); ++p)
    if (view.face[p] >= 0) regions[regionOf(scene, scene.faces()[size_t(view.face[p])])].push_back(p);
  std::mt19937_64 pick(o.seed);
  std::vector<std::pair<std::string, size_t>> samples;
  for (auto& [name, pixels] : regions) {
    std::shuffle(pixels.begin(), pixels.end(), pick);
    for (size_t k = 0; k < pixels.size() && k < size_t(o.pixels); ++k) samples.emplace_back(name, pixels[k]);
  }

  const bench::DirectLight exactDirect = [&](uint32_t faceIndex, const Vec3& q) {
    return exact.evaluate(q, scene.faces()[faceIndex].plane.normal).irradiance;
  };
  std::vector<Vec3> meshTraced(samples.size()), exactTraced(samples.size());
  parallel.forEach(samples.size(), [&](size_t k) {
    const size_t p = samples[k].second;
    const Vec3 n = scene.faces()[size_t(view.face[p])].plane.normal;
    std::mt19937_64 a(o.seed * 1000003 + k), b = a;  // the same directions for both
    meshTraced[k] = bench::pathTracedIndirect(scene, rays, lookup, view.position[p], n, o.paths, a).mean;
    exactTraced[k] = bench::pathTracedIndirect(scene, rays, exactDirect, view.position[p], n, o.paths, b).mean;
  });

  std::map<std::string, Sums> sums;
  for (size_t k = 0; k < samples.size(); ++k) {
    const double e = brightness(exactTraced[k]);
    if (!(e > 0)) continue;
    Sums& s = sums[samples[k].first];
    const double sensor = brightness(image.irradiance[samples[k].second]), traced = brightness(meshTraced[k]);
    ++s.pixels;
    s.sensors += sensor, s.meshTraced += traced, s.exactTraced += e;
    s.sensorsOverExact += sensor / e, s.sensorsOverExactSquares += (sensor / e) * (sensor / e);
    s.meshOverExact += traced / e, s.meshOverExactSquares += (traced / e) * (traced / e);
  }
  std::printf("%s at %d², tolerance %g, sensors %d², %d paths a pixel (bias: mean of per-pixel ratios − 1, ± its "
              "standard error)\n", o.scene.c_str(), o.size, engine.settings().meshTolerance, o.sensorSize, o.paths);
  std::printf("%-18s %6s %12s %14s %14s %22s %22s\n", "region", "pixels", "sensors", "traced (mesh)",
              "traced (exact)", "sensors vs exact %", "mesh vs exact %");
  json rows = json::array();
  for (const auto& [name, s] : sums) {
    const double n = s.pixels;
    const auto bias = [&](double sum, double squares) {
      const double mean = sum / n, spread = std::sqrt(std::max(0.0, squares / n - mean * mean) / std::max(1.0, n - 1));
      return std::pair{100 * (mean - 1), 100 * spread};
    };
    const auto [sensorBias, sensorSpread] = bias(s.sensorsOverExact, s.sensorsOverExactSquares);
    const auto [meshBias, meshSpread] = bias(s.meshOverExact, s.meshOverExactSquares);
    std::printf("%-18s %6d %12.4f %14.4f %14.4f %14.2f ± %5.2f %14.2f ± %5.2f\n", name.c_str(), s.pixels,
                s.sensors / n, s.meshTraced / n, s.exactTraced / n, sensorBias, sensorSpread, meshBias, meshSpread);
    rows.push_back({{"region", name}, {"pixels", s.pixels}, {"sensors", s.sensors / n},
                    {"traced_mesh", s.meshTraced / n}, {"traced_exact", s.exactTraced / n},
                    {"sensors_vs_exact_percent", sensorBias}, {"sensors_vs_exact_stderr", sensorSpread},
                    {"mesh_vs_exact_percent", meshBias}, {"mesh_vs_exact_stderr", meshSpread}});
  }
  if (!o.jsonOut.empty()) std::ofstream(o.jsonOut) << rows.dump(2) << "\n";
  return 0;
} catch (const std::exception& error) {
  std::fprintf(stderr, "penumbra-gi-region-bench: %s\n", error.what());
  return 2;
}
