// `penumbra render`: an image of a scene lit by its DM mesh (or by the exact reference).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/progress_bar.h"
#include "core/engine/engine.h"
#include "core/engine/seconds_since.h"
#include "core/gi/sensor_map.h"
#include "core/render/dm_visibility.h"
#include "core/render/renderer.h"
#include "imageio/image_encoding.h"
#include "protocol/json_text.h"
#include "protocol/mesh_json.h"
#include "protocol/scene_json.h"

namespace penumbra::cli {

namespace {

constexpr size_t kMaxCameraBytes = size_t(1) << 20;

// --camera is inline JSON (starts with '{') or a file holding it. It is validated by the scene
// reader itself (as the scene's "camera"), so errors name the same key paths: camera.fov_y_deg.
Camera cameraFromOption(const Scene& scene, const std::string& value) {
  const size_t first = value.find_first_not_of(" \t\r\n");
  const std::string text = first != std::string::npos && value[first] == '{'
                               ? value
                               : protocol::readTextFile(value, kMaxCameraBytes);
  nlohmann::json document = protocol::sceneToJson(scene);
  document["camera"] = protocol::parseJsonText(text, kMaxCameraBytes, protocol::kMaxJsonDepth);
  return *protocol::sceneFromJson(document).camera();
}

// --gi sensors and its settings (README "Global illumination").
std::optional<gi::GiSettings> giFromOptions(const Args& args) {
  const auto mode = args.option("gi");
  if (!mode) {
    for (const char* name : {"sensor-size", "tile", "threshold", "bounces", "filter"})
      if (args.option(name)) throw UsageError(std::string("--") + name + " needs --gi sensors");
    return std::nullopt;
  }
  if (*mode != "sensors") throw UsageError("--gi must be 'sensors', got '" + *mode + "'");
  if (args.flag("reference")) throw UsageError("--gi lights bounces with the DM mesh: leave out --reference");
  gi::GiSettings gi;
  gi.sensorSize = args.intOption("sensor-size", gi.sensorSize, 1, gi::SensorMap::kMaxSize);
  gi.placement.tile = args.intOption("tile", gi.placement.tile, 1, 256);
  gi.placement.threshold = args.doubleOption("threshold", gi.placement.threshold);
  if (!(gi.placement.threshold >= 0 && gi.placement.threshold <= 10))
    throw UsageError("--threshold must be in [0, 10]");
  gi.bounces = args.intOption("bounces", gi.bounces, 1, gi::GiSettings::kMaxBounces);
  gi.filterRadius = args.intOption("filter", gi.filterRadius, 0, 16);
  return gi;
}

}  // namespace

int runRender(const Args& args) {
  args.allowOnly({"out", "width", "height", "camera", "mesh", "mesh-tolerance", "gi", "sensor-size", "tile", "threshold", "bounces", "filter", "exposure"});
  const std::string scenePath = args.positional(0, "SCENE");
  const auto out = args.option("out");
  if (!out) throw UsageError("render needs --out IMAGE (.png or .exr)");
  try {
    imageio::imageFormatForPath(*out);  // refuse a bad extension before any work
  } catch (const std::invalid_argument& error) {
    throw UsageError(error.what());
  }
  imageio::loadImageModule();  // a missing image module fails now, not after the build
  RenderSettings settings;
  settings.width = args.intOption("width", 512, 1, RenderSettings::kMaxSize);
  settings.height = args.intOption("height", 512, 1, RenderSettings::kMaxSize);
  settings.reference = args.flag("reference");
  const Scene scene = protocol::loadSceneFile(scenePath);
  if (const auto camera = args.option("camera")) settings.camera = cameraFromOption(scene, *camera);
  settings.gi = giFromOptions(args);
  settings.exposure = args.doubleOption("exposure", 0);
  if (!(settings.exposure >= 0 && settings.exposure < 1e12))
    throw UsageError("--exposure must be a non-negative number (0: automatic)");

  const auto meshStart = std::chrono::steady_clock::now();
  Mesh mesh;
  std::unique_ptr<Engine> engine;  // kept: microfacet shading reads its cells' occluder lists
  if (const auto meshPath = args.option("mesh")) {
    mesh = protocol::loadMeshFile(*meshPath, scene);
  } else if (!settings.reference) {
    BuildBars bars;
    EngineSettings engineSettings;
    engineSettings.meshTolerance = meshToleranceOption(args);
    engine = std::make_unique<Engine>(scene, engineSettings, bars.progress());
    bars.finish();
    mesh = engine->mesh();
    settings.occluders = dmOccluderLists(*engine);
  }
  const double meshSeconds = secondsSince(meshStart);

  ProgressBar bar(settings.reference ? "render (reference)" : "render");
  // GI reports every 64 sensors: a line each time a twentieth of the pixels more are sensed.
  const size_t sensorStep = std::max<size_t>(1, size_t(settings.width) * size_t(settings.height) / 20);
  size_t nextSensorLine = sensorStep;
  const RenderedImage image = render(scene, mesh, settings, [&](size_t done, size_t total) {
    if (total == 0) {  // GI: sensors so far, before the rows
      if (done < nextSensorLine) return;
      std::fprintf(stderr, "gi: %zu sensors placed\n", done);
      nextSensorLine = (done / sensorStep + 1) * sensorStep;
    } else {
      bar.update(done, total);
    }
  });
  bar.finish();
  const auto encodeStart = std::chrono::steady_clock::now();
  imageio::writeImageFile(image, *out);
  const double encodeSeconds = secondsSince(encodeStart);

  if (args.flag("stats")) {
    const nlohmann::json stats = {
        {"width", image.width},
        {"height", image.height},
        {"shading", settings.reference ? "reference" : "mesh"},
        {"mesh_triangles", mesh.triangleCount()},
        // What the mesh's interpolation is within (0: not refined, or a loaded mesh).
        {"mesh_tolerance", settings.reference ? nlohmann::json() : nlohmann::json(mesh.tolerance)},
        {"mesh_capped_cells", mesh.cappedCells},
        {"surface_pixels", image.surfacePixels},
        {"light_pixels", image.lightPixels},
        {"exposure", image.exposure},
        {"gi", image.gi ? nlohmann::json{{"sensors", image.gi->placement.sensors},
                                         {"sensors_per_level", image.gi->placement.sensorsPerLevel},
                                         {"interpolated_pixels", image.gi->placement.interpolated},
                                         {"vertex_sensors", image.gi->vertexSensors},
                                         {"bounce_change", image.gi->bounceChange},
                                         {"seconds", image.gi->seconds}}
                        : nlohmann::json()},
        {"seconds", {{"mesh", meshSeconds}, {"render", image.seconds}, {"encode", encodeSeconds}}},
        {"megapixels_per_second", image.seconds > 0 ? 1e-6 * image.width * image.height / image.seconds : 0.0}};
    std::printf("%s\n", stats.dump(2).c_str());
  } else {
    std::printf("wrote %s: %dx%d, %s shading (render %.3f s, mesh %.3f s, encode %.3f s)\n", out->c_str(),
                image.width, image.height, settings.reference ? "reference" : "mesh", image.seconds,
                meshSeconds, encodeSeconds);
    if (!settings.reference && mesh.tolerance > 0)  // built here, or a mesh file's own statement
      std::printf("direct light interpolated within %g of the local unshadowed light (%zu cells capped)\n",
                  mesh.tolerance, mesh.cappedCells);
    else if (!settings.reference)
      std::printf("direct light interpolated between exact vertices, not refined (no bound)\n");
    if (image.gi)
      std::printf("gi: %zu sensors (%zu pixels interpolated), %.3f s of the render\n", image.gi->placement.sensors,
                  image.gi->placement.interpolated, image.gi->seconds);
  }
  return 0;
}

}  // namespace penumbra::cli
