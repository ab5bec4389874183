// The independent reference for sensor GI (core/gi): the indirect irradiance at a point by Monte
// Carlo, one diffuse bounce — cosine-weighted random directions (uniform disc points lifted to
// the hemisphere, drawn with std::mt19937_64; none of core/gi's code), and at the first
// front-facing surface the radiance albedo/π · E_direct, from the DM mesh (the same direct light
// the sensors see) or from any other source of direct light (the exact reference: then nothing
// of the display mesh either). Lights met first contribute 0 (their light is the direct part).
// Shares with core/gi only the Embree scene (RayScene) and, by default, the mesh lookup.
#pragma once

#include <cstdint>
#include <functional>
#include <random>

#include "core/raycast/mesh_lookup.h"
#include "core/raycast/ray_scene.h"

namespace penumbra::bench {

struct PathTracedIndirect {
  Vec3 mean{0.0};      // W·m⁻²
  Vec3 stdError{0.0};  // of the mean
};

// The direct irradiance at a point of a face (its index in Scene::faces()).
using DirectLight = std::function<Vec3(uint32_t faceIndex, const Vec3& position)>;

// The indirect irradiance at p (on a face with unit front normal n), `samples` paths.
PathTracedIndirect pathTracedIndirect(const Scene& scene, const RayScene& rays, const DirectLight& direct,
                                      const Vec3& p, const Vec3& n, int samples, std::mt19937_64& rng);
// The same with the direct light the display mesh interpolates.
PathTracedIndirect pathTracedIndirect(const Scene& scene, const RayScene& rays, const MeshLookup& direct,
                                      const Vec3& p, const Vec3& n, int samples, std::mt19937_64& rng);

}  // namespace penumbra::bench
