// Fuzz target: cameras made of extreme doubles (issue 36: values that made Embree's ray
// assertion abort the server). An input is a flags byte (bit 0: orthographic), a 16-bit mask of
// the camera fields it sets, then one 8-byte double per set field in the order position xyz,
// target xyz, up xyz, fov_y_deg, height, near, far (fields past the input's end keep the tiny
// scene's default camera). Checked, on the tiny scene:
//   - render() refuses (CameraError) exactly the cameras validateCamera refuses, and renders the
//     others (a 6 × 4 image, one thread) without any other exception;
//   - the scene loader agrees: the camera as scene JSON is accepted iff validateCamera accepts
//     it (the refusal names `camera.<key>`);
//   - RayScene never hands Embree a ray its assertion refuses: intersect / occluded / blockers
//     with the camera's numbers as origin, direction and interval return (a miss at worst).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>

#include "core/engine/engine.h"
#include "core/raycast/ray_scene.h"
#include "core/render/renderer.h"
#include "core/scene/camera_limits.h"
#include "fuzz_support.h"

using namespace penumbra;

namespace {

struct Lit {
  std::unique_ptr<Engine> engine;
  Mesh mesh;
};

const Lit& lit() {
  static const Lit l = [] {
    Lit made;
    EngineSettings settings;
    settings.threads = 1;
    made.engine = std::make_unique<Engine>(fuzz::tinyScene(), settings);
    made.mesh = made.engine->mesh();
    return made;
  }();
  return l;
}

const RayScene& rays() {
  static const RayScene r(fuzz::tinyScene());
  return r;
}

Camera cameraOf(const uint8_t* data, size_t size) {
  Camera camera = defaultCamera(fuzz::tinyScene().bounds());
  if (size < 3) return camera;
  if (data[0] & 1) camera.projection = Camera::Projection::Orthographic;
  const unsigned mask = unsigned(data[1]) | unsigned(data[2]) << 8;
  double* fields[] = {&camera.position.x, &camera.position.y, &camera.position.z, &camera.target.x,
                      &camera.target.y,   &camera.target.z,   &camera.up.x,       &camera.up.y,
                      &camera.up.z,       &camera.fovYDeg,    &camera.height,     &camera.near,
                      &camera.far};
  size_t at = 3;
  for (size_t f = 0; f < std::size(fields); ++f) {
    if (!(mask >> f & 1u)) continue;
    if (at + 8 > size) break;
    std::memcpy(fields[f], data + at, 8);
    at += 8;
  }
  return camera;
}

bool allFinite(const Camera& c) {
  const double values[] = {c.position.x, c.position.y, c.position.z, c.target.x, c.target.y,
                           c.target.z,   c.up.x,       c.up.y,       c.up.z,     c.fovYDeg,
                           c.height,     c.near,       c.far};
  for (double v : values)
    if (!std::isfinite(v)) return false;
  return true;
}

nlohmann::json cameraJson(const Camera& c) {
  auto vec = [](const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
  return {{"position", vec(c.position)},
          {"target", vec(c.target)},
          {"up", vec(c.up)},
          {"projection",
           c.projection == Camera::Projection::Perspective ? "perspective" : "orthographic"},
          {"fov_y_deg", c.fovYDeg},
          {"height", c.height},
          {"near", c.near},
          {"far", c.far}};
}

void checkRays(const Camera& c) {
  const Vec3 dir = c.target - c.position;
  (void)rays().intersect(c.position, dir, c.near, c.far);
  (void)rays().intersect(c.position, c.up, 0.0, INFINITY, kAllRays);
  (void)rays().intersectFront(c.position, dir, c.near);
  (void)rays().occluded(c.position, c.target);
  (void)rays().blockers(c.target, c.up);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const Camera camera = cameraOf(data, size);
  const Scene& scene = fuzz::tinyScene();
  bool valid = true;
  try {
    validateCamera(camera, scene.bounds());
  } catch (const CameraError& error) {
    valid = false;
    fuzz::note(std::string("refused: ") + error.what());
  }
  checkRays(camera);

  RenderSettings settings;
  settings.width = 6;
  settings.height = 4;
  settings.threads = 1;
  settings.camera = camera;
  try {
    const RenderedImage image = render(scene, lit().mesh, settings);
    fuzz::check(valid, "render() drew a camera validateCamera refuses");
    fuzz::check(image.linear.size() == 3u * 6 * 4, "image of the wrong size");
  } catch (const CameraError&) {
    fuzz::check(!valid, "render() refused a camera validateCamera accepts");
  }

  if (allFinite(camera)) {  // JSON holds finite numbers only
    nlohmann::json root = nlohmann::json::parse(fuzz::kTinySceneJson);
    root["camera"] = cameraJson(camera);
    try {
      (void)protocol::sceneFromJson(root);
      fuzz::check(valid, "the scene loader accepted a camera validateCamera refuses");
    } catch (const protocol::ValidationError& error) {
      fuzz::check(!valid || error.path().rfind("camera", 0) != 0,
                  std::string("the scene loader refused a valid camera: ") + error.what());
    }
  }
  return 0;
}
