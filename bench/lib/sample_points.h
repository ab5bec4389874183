// Seeded random points on the receiving faces of a scene (area-uniform over all
// of them), for benchmarks and property tests. Pure function; thread-safe.
#pragma once

#include <cstdint>
#include <vector>

#include "core/scene/scene.h"

namespace penumbra {

struct SurfacePoint {
  FaceId face;
  Vec3 position{0.0};
  Vec3 normal{0.0};
};

std::vector<SurfacePoint> sampleReceivingPoints(const Scene& scene, size_t count, uint64_t seed);

}  // namespace penumbra
