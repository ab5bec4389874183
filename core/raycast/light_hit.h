// Where a ray meets the emitting front of an area light (lights are not in the RayScene):
// shared by the renderer's camera rays and the GI sensors' rays. Pure functions; thread-safe.
#pragma once

#include <optional>
#include <vector>

#include "core/scene/scene.h"

namespace penumbra {

// Ray parameter t >= 0 where origin + t·dir meets the front of the light (`plane` is
// light.plane()), if it does; seen from behind or edge-on a light is not hit.
std::optional<double> frontLightHit(const Light& light, const Plane& plane, const Vec3& origin,
                                    const Vec3& dir);

struct LightHit {
  size_t light = 0;
  double t = 0;
};
// The closest light front hit with t <= tMax (planes[l] = lights[l].plane()).
std::optional<LightHit> closestLightHit(const std::vector<Light>& lights, const std::vector<Plane>& planes,
                                        const Vec3& origin, const Vec3& dir, double tMax);

}  // namespace penumbra
