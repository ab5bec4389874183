#include "core/scene/camera_limits.h"

#include <cmath>
#include <cstdio>

#include "core/geom/tolerance.h"

namespace penumbra {

namespace {

std::string shown(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

bool finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void checkFinite(const Camera& camera) {
  const std::pair<const char*, Vec3> points[] = {
      {"position", camera.position}, {"target", camera.target}, {"up", camera.up}};
  for (const auto& [key, value] : points)
    if (!finite(value)) throw CameraError(key, "every component must be a finite number");
  const std::pair<const char*, double> numbers[] = {{"fov_y_deg", camera.fovYDeg},
                                                    {"height", camera.height},
                                                    {"near", camera.near},
                                                    {"far", camera.far}};
  for (const auto& [key, value] : numbers)
    if (!std::isfinite(value)) throw CameraError(key, "must be a finite number");
}

void checkDepth(const Camera& camera, double size) {
  if (!(camera.near > 0))
    throw CameraError("near", "near must be positive, got " + shown(camera.near));
  if (!(camera.near >= CameraLimits::kMinNear * size))
    throw CameraError("near", "near " + shown(camera.near) + " is below " +
                                  shown(CameraLimits::kMinNear) + " × the scene's size (" +
                                  shown(size) + ")");
  if (!(camera.far > camera.near))
    throw CameraError("far", "far must be greater than near (" + shown(camera.near) + "), got " +
                                 shown(camera.far));
  if (!(camera.far <= CameraLimits::kMaxFar * size))
    throw CameraError("far", "far " + shown(camera.far) + " is beyond " +
                                 shown(CameraLimits::kMaxFar) + " × the scene's size (" +
                                 shown(size) + ")");
  if (!(camera.far / camera.near <= CameraLimits::kMaxDepthRatio))
    throw CameraError("near", "far / near is " + shown(camera.far / camera.near) + ", more than " +
                                  shown(CameraLimits::kMaxDepthRatio) +
                                  ": raise near or lower far");
}

void checkProjection(const Camera& camera, double size) {
  if (camera.projection == Camera::Projection::Perspective) {
    if (!(camera.fovYDeg >= CameraLimits::kMinFovYDeg &&
          camera.fovYDeg <= CameraLimits::kMaxFovYDeg))
      throw CameraError("fov_y_deg", "fov_y_deg " + shown(camera.fovYDeg) + " is outside [" +
                                         shown(CameraLimits::kMinFovYDeg) + ", " +
                                         shown(CameraLimits::kMaxFovYDeg) + "] degrees");
    return;
  }
  const double low = CameraLimits::kMinOrthoHeight * size,
               high = CameraLimits::kMaxOrthoHeight * size;
  if (!(camera.height >= low && camera.height <= high))
    throw CameraError("height", "orthographic height " + shown(camera.height) + " is outside [" +
                                    shown(low) + ", " + shown(high) + "] (" +
                                    shown(CameraLimits::kMinOrthoHeight) + " to " +
                                    shown(CameraLimits::kMaxOrthoHeight) + " × the scene's size)");
}

// Eye and target near enough to the scene that float rays stay meaningful; a view direction;
// up not along it.
void checkPlacement(const Camera& camera, const Bounds& bounds, double size) {
  const double reach = CameraLimits::kMaxReach * size;
  const std::pair<const char*, Vec3> points[] = {{"position", camera.position},
                                                 {"target", camera.target}};
  for (const auto& [key, value] : points)
    if (!(glm::length(value - bounds.center()) <= reach))
      throw CameraError(key, std::string(key) + " is farther than " +
                                 shown(CameraLimits::kMaxReach) + " × the scene's size (" +
                                 shown(reach) + ") from the scene's centre");
  const Vec3 view = camera.target - camera.position;
  if (!(glm::length(view) > Tolerance::forSize(size).length()))
    throw CameraError("target", "target is at the camera position (no view direction)");
  const double upLength = glm::length(camera.up);
  if (!(upLength > 0) ||
      !(glm::length(glm::cross(glm::normalize(view), camera.up)) > kRelativePlanarity * upLength))
    throw CameraError("up", "up is parallel to the view direction");
}

}  // namespace

void validateCamera(const Camera& camera, const Bounds& sceneBounds) {
  checkFinite(camera);
  const double diagonal = sceneBounds.diagonal();
  if (!std::isfinite(diagonal) || !finite(sceneBounds.center()))
    throw CameraError("position", "the scene's bounds are not finite");
  const double size = diagonal > 0 ? diagonal : 1.0;
  checkDepth(camera, size);
  checkProjection(camera, size);
  checkPlacement(camera, sceneBounds, size);
}

}  // namespace penumbra
