// A sensor (seed 001): the light a surface point receives from the rest of the scene, captured
// over a SensorMap's directions and summed with the weights F_ij:
//   E_indirect(p) = π Σ_ij F_ij L_o(q_ij),   q_ij the first front-facing surface along ω_ij.
// The paper estimates L_o of a reflecting q as "diffuse colour × ε"; here it is what the caller
// says (the DM's exact direct irradiance: albedo/π · E(q), plus earlier bounces). A ray that
// meets a light's front first contributes 0: that light reaches p as direct light, which the DM
// has exactly. Immutable after construction; irradiance() is thread-safe.
#pragma once

#include <functional>
#include <vector>

#include "core/gi/sensor_map.h"
#include "core/raycast/ray_scene.h"

namespace penumbra::gi {

// Radiance leaving a front-facing hit towards the ray's origin.
using OutgoingRadianceFn = std::function<Vec3(const RayScene::Hit& hit)>;

class Sensor {
 public:
  // Borrows everything; keep it alive.
  Sensor(const Scene& scene, const RayScene& rays, const SensorMap& map, OutgoingRadianceFn outgoing);

  // Indirect irradiance at p on a face with front normal n (unit).
  Vec3 irradiance(const Vec3& p, const Vec3& n) const;
  // The radiance arriving at p from direction dir (unit): 0 from lights and from nothing.
  Vec3 incoming(const Vec3& p, const Vec3& dir) const;

  const SensorMap& map() const { return map_; }

 private:
  const Scene& scene_;
  const RayScene& rays_;
  const SensorMap& map_;
  OutgoingRadianceFn outgoing_;
  std::vector<Plane> lightPlanes_;
  double tNear_ = 0;  // skips the sensor's own face
};

// L_o of a diffuse hit from the irradiance at it: albedo/π · irradiance(faceIndex, q) on a
// face's front, 0 on its back (faces receive light on their front only).
OutgoingRadianceFn diffuseOutgoing(const Scene& scene,
                                   std::function<Vec3(uint32_t faceIndex, const Vec3& q)> irradiance);

}  // namespace penumbra::gi
