// `penumbra-mesh-error-bench [--scene FILE,...] [--dense-cubes N,...] [--model NAME --triangles N]
// [--size N,...: 0 = build only] [--threads T] [--tolerance X] [--min-edge-divisions D] [--json OUT]` (docs/BENCHMARKS.md "Direct light
// between vertices"): builds each scene's engine and display mesh (timed), then counts the
// pixels of its camera view whose interpolated direct light is off the exact reference by more
// than 1 % and 2 % of the scene's bright level (bench/lib/direct_light_error.h), and the same for
// the rendered images (`penumbra render` against `--reference`: radiance, bright level = the
// reference image's 1 / exposure).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/lib/direct_light_error.h"
#include "core/engine/engine.h"
#include "core/engine/seconds_since.h"
#include "core/render/renderer.h"
#include "protocol/scene_json.h"
#include "scenegen/dense_scene.h"
#include "scenegen/model_scene.h"

using namespace penumbra;
using nlohmann::json;

namespace {

std::vector<std::string> list(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream items(text);
  for (std::string item; std::getline(items, item, ',');) out.push_back(item);
  return out;
}

struct Options {
  std::vector<std::pair<std::string, Scene>> scenes;  // name, scene
  std::vector<int> sizes{256};
  int threads = 2;
  double tolerance = -1;  // < 0: the engine's default
  double minEdgeDivisions = 0;  // 0: the engine's default
  std::string jsonOut;
};

Options parse(int argc, char** argv) {
  Options o;
  std::string model;
  int triangles = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string name = argv[i];
    if (i + 1 >= argc) throw std::invalid_argument(name + " needs a value");
    const std::string value = argv[++i];
    if (name == "--scene") {
      for (const std::string& path : list(value)) o.scenes.emplace_back(path, protocol::loadSceneFile(path));
    } else if (name == "--dense-cubes") {
      for (const std::string& n : list(value)) {
        DenseSceneOptions dense;
        dense.boxes = std::stoi(n);
        o.scenes.emplace_back("dense " + n, makeDenseScene(dense));
      }
    } else if (name == "--model") {
      model = value;
    } else if (name == "--triangles") {
      triangles = std::stoi(value);
    } else if (name == "--size") {
      o.sizes.clear();
      for (const std::string& n : list(value)) o.sizes.push_back(std::stoi(n));
    } else if (name == "--threads") {
      o.threads = std::stoi(value);
    } else if (name == "--tolerance") {
      o.tolerance = std::stod(value);
    } else if (name == "--min-edge-divisions") {
      o.minEdgeDivisions = std::stod(value);
    } else if (name == "--json") {
      o.jsonOut = value;
    } else {
      throw std::invalid_argument("unknown option " + name);
    }
  }
  if (!model.empty()) {
    ModelSceneOptions options;
    const auto kind = modelKindFromName(model);
    if (!kind) throw std::invalid_argument("--model must be one of " + modelKindNames());
    options.kind = *kind;
    options.triangles = triangles;
    o.scenes.emplace_back(model + " " + std::to_string(triangles), makeModelScene(options));
  }
  if (o.scenes.empty()) throw std::invalid_argument("no scene: --scene, --dense-cubes or --model");
  return o;
}

// Pixels of the default render off the reference render by more than 1 % / 2 % of the
// reference's bright level (1 / its automatic exposure), largest channel.
json imageCounts(const Scene& scene, const Mesh& mesh, int size, int threads) {
  RenderSettings settings;
  settings.width = settings.height = size;
  settings.threads = threads;
  const RenderedImage meshImage = render(scene, mesh, settings);
  settings.reference = true;
  const RenderedImage exact = render(scene, mesh, settings);
  const double bright = 1.0 / exact.exposure;
  size_t one = 0, two = 0;
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const Vec3 d = glm::abs(meshImage.pixel(i, j) - exact.pixel(i, j));
      const double relative = std::max({d.x, d.y, d.z}) / bright;
      one += relative > 0.01 ? 1 : 0;
      two += relative > 0.02 ? 1 : 0;
    }
  return {{"over_1pct", one}, {"over_2pct", two}, {"bright_radiance", bright}};
}

// The pixels over 1 %: where, which object, the exact and interpolated values, and the error
// relative to the local unshadowed level (what the mesh's tolerance is relative to).
json missesJson(const Scene& scene, const DirectLightError& e) {
  json out = json::array();
  for (const DirectLightMiss& m : e.misses) {
    const Face& face = scene.faces()[m.face];
    out.push_back({{"x", m.x}, {"y", m.y}, {"object", scene.object(face.id.object).id}, {"face", face.id.face},
                   {"position", {m.position.x, m.position.y, m.position.z}}, {"exact", m.exact}, {"mesh", m.mesh},
                   {"unshadowed", m.unshadowed},
                   {"relative_to_local", m.unshadowed > 0 ? std::abs(m.mesh - m.exact) / m.unshadowed : 0.0}});
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
  json rows = json::array();
  std::printf("%-28s %9s %9s %8s %6s %9s %9s %8s %10s %10s %12s\n", "scene", "vertices", "triangles", "build s",
              "size", ">1% irr", ">2% irr", "worst %", ">1% image", ">2% image", ">1% > bright");
  for (const auto& [name, scene] : o.scenes) {
    EngineSettings settings;
    settings.threads = o.threads;
    if (o.tolerance >= 0) settings.meshTolerance = o.tolerance;
    if (o.minEdgeDivisions > 0) settings.meshRefineMinEdgeDivisions = o.minEdgeDivisions;
    const auto start = std::chrono::steady_clock::now();
    Engine engine(scene, settings);
    const Mesh mesh = engine.mesh();
    const double seconds = secondsSince(start);
    const Camera camera = scene.camera().value_or(defaultCamera(scene.bounds()));
    std::printf("%-28s %9zu %9zu %8.2f  (mesh %.2f s, %zu cells capped)\n", name.c_str(), mesh.vertexCount(),
                mesh.triangleCount(), seconds, engine.stats().seconds.triangulation, mesh.cappedCells);
    for (int size : o.sizes) {
      if (size <= 0) continue;  // --size 0: the build alone
      const DirectLightError e = directLightError(scene, mesh, camera, size, size, Parallel(o.threads));
      const json image = imageCounts(scene, mesh, size, o.threads);
      std::printf("%-28s %9zu %9zu %8.2f %6d %9zu %9zu %8.2f %10zu %10zu %12zu\n", name.c_str(), mesh.vertexCount(),
                  mesh.triangleCount(), seconds, size, e.overOnePercent, e.overTwoPercent, 100 * e.worstRelative,
                  image["over_1pct"].get<size_t>(), image["over_2pct"].get<size_t>(), e.overOnePercentAboveBright);
      rows.push_back({{"scene", name},
                      {"vertices", mesh.vertexCount()},
                      {"triangles", mesh.triangleCount()},
                      {"build_seconds", seconds},
                      {"mesh_seconds", engine.stats().seconds.triangulation},
                      {"tolerance", mesh.tolerance},
                      {"capped_cells", mesh.cappedCells},
                      {"size", size},
                      {"pixels", e.pixels},
                      {"bright_irradiance", e.brightLevel},
                      {"over_1pct", e.overOnePercent},
                      {"over_2pct", e.overTwoPercent},
                      {"over_1pct_above_bright", e.overOnePercentAboveBright},
                      {"worst", {{"relative", e.worstRelative}, {"x", e.worstX}, {"y", e.worstY},
                                 {"mesh", e.worstMesh}, {"exact", e.worstExact}}},
                      {"image", image},
                      {"misses", missesJson(scene, e)}});
    }
  }
  if (!o.jsonOut.empty()) std::ofstream(o.jsonOut) << rows.dump(2) << "\n";
  return 0;
} catch (const std::exception& error) {
  std::fprintf(stderr, "penumbra-mesh-error-bench: %s\n", error.what());
  return 2;
}
