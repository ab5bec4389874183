// `penumbra render`: an image of a scene lit by its DM mesh (or by the exact reference).
#include <chrono>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "core/engine/engine.h"
#include "core/render/dm_visibility.h"
#include "core/render/renderer.h"
#include "protocol/json_text.h"
#include "protocol/mesh_json.h"
#include "protocol/scene_json.h"
#include "cli/commands.h"
#include "server/image_encoding.h"
#include "cli/progress_bar.h"

namespace penumbra::cli {

namespace {

constexpr size_t kMaxCameraBytes = size_t(1) << 20;

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

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

}  // namespace

int runRender(const Args& args) {
  args.allowOnly({"out", "width", "height", "camera", "mesh"});
  const std::string scenePath = args.positional(0, "SCENE");
  const auto out = args.option("out");
  if (!out) throw UsageError("render needs --out IMAGE (.png or .exr)");
  try {
    server::imageFormatForPath(*out);  // refuse a bad extension before any work
  } catch (const std::invalid_argument& error) {
    throw UsageError(error.what());
  }
  server::loadImageModule();  // a missing image module fails now, not after the build
  RenderSettings settings;
  settings.width = args.intOption("width", 512, 1, RenderSettings::kMaxSize);
  settings.height = args.intOption("height", 512, 1, RenderSettings::kMaxSize);
  settings.reference = args.flag("reference");
  const Scene scene = protocol::loadSceneFile(scenePath);
  if (const auto camera = args.option("camera")) settings.camera = cameraFromOption(scene, *camera);

  const auto meshStart = std::chrono::steady_clock::now();
  Mesh mesh;
  std::unique_ptr<Engine> engine;  // kept: microfacet shading reads its cells' occluder lists
  if (const auto meshPath = args.option("mesh")) {
    mesh = protocol::loadMeshFile(*meshPath, scene);
  } else if (!settings.reference) {
    ProgressBar casting("casting"), illumination("illumination");
    engine = std::make_unique<Engine>(scene, EngineSettings{}, [&](const char* step, size_t done, size_t total) {
      (std::string(step) == "casting" ? casting : illumination).update(done, total);
    });
    casting.finish();
    illumination.finish();
    mesh = engine->mesh();
    settings.occluders = dmOccluderLists(*engine);
  }
  const double meshSeconds = secondsSince(meshStart);

  ProgressBar bar(settings.reference ? "render (reference)" : "render");
  const RenderedImage image =
      render(scene, mesh, settings, [&](size_t done, size_t total) { bar.update(done, total); });
  bar.finish();
  const auto encodeStart = std::chrono::steady_clock::now();
  server::writeImageFile(image, *out);
  const double encodeSeconds = secondsSince(encodeStart);

  if (args.flag("stats")) {
    const nlohmann::json stats = {
        {"width", image.width},
        {"height", image.height},
        {"shading", settings.reference ? "reference" : "mesh"},
        {"mesh_triangles", mesh.triangleCount()},
        {"surface_pixels", image.surfacePixels},
        {"light_pixels", image.lightPixels},
        {"exposure", image.exposure},
        {"seconds", {{"mesh", meshSeconds}, {"render", image.seconds}, {"encode", encodeSeconds}}},
        {"megapixels_per_second", image.seconds > 0 ? 1e-6 * image.width * image.height / image.seconds : 0.0}};
    std::printf("%s\n", stats.dump(2).c_str());
  } else {
    std::printf("wrote %s: %dx%d, %s shading (render %.3f s, mesh %.3f s, encode %.3f s)\n", out->c_str(),
                image.width, image.height, settings.reference ? "reference" : "mesh", image.seconds,
                meshSeconds, encodeSeconds);
  }
  return 0;
}

}  // namespace penumbra::cli
