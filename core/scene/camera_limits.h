// The one check every camera passes before it is used (the scene loader, the image route, the CLI,
// the renderer): every number finite, the depth range and its ratio bounded, the field of view and
// the orthographic height in sane ranges, the eye and target within reach of the scene. Pure
// functions of plain values; thread-safe. (Issue 36: numbers that made Embree assert.)
#pragma once

#include <stdexcept>
#include <string>

#include "core/scene/scene.h"

namespace penumbra {

// The documented limits (SCENE_FORMAT.md "Camera"). Lengths relative to the scene's size S (the
// diagonal of its bounds, lights included).
struct CameraLimits {
  static constexpr double kMinFovYDeg = 0.01;
  static constexpr double kMaxFovYDeg = 179;
  static constexpr double kMaxDepthRatio = 1e7;    // far / near
  static constexpr double kMaxReach = 1e4;         // eye, target within kMaxReach·S of the centre
  static constexpr double kMaxFar = 1e5;           // far ≤ kMaxFar·S
  static constexpr double kMinNear = 1e-7;         // near ≥ kMinNear·S
  static constexpr double kMinOrthoHeight = 1e-6;  // orthographic height in [1e-6·S, 1e5·S]
  static constexpr double kMaxOrthoHeight = 1e5;
};

// A camera refused by validateCamera: `key` is the camera field at fault as the scene format
// names it ("near", "far", "fov_y_deg", "height", "position", "target", "up"), so each caller can
// name its own key path (camera.near, query.near, query.ortho_height).
class CameraError : public std::invalid_argument {
 public:
  CameraError(std::string key, const std::string& problem)
      : std::invalid_argument("camera." + key + ": " + problem),
        key_(std::move(key)),
        problem_(problem) {}
  const std::string& key() const { return key_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string key_;
  std::string problem_;
};

// Throws CameraError on the first field that breaks CameraLimits for a scene with these bounds.
// Only the active projection's size (fov_y_deg or height) is range-checked; both must be finite.
void validateCamera(const Camera& camera, const Bounds& sceneBounds);

}  // namespace penumbra
