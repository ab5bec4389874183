// Seeded generator of dense benchmark scenes: boxes of random non-uniform size and
// orientation floating in a 6 × 3 × 6 m room under one 1 m² ceiling light. Pure; thread-safe.
#pragma once

#include <cstdint>

#include "core/scene/scene.h"

namespace penumbra {

struct DenseSceneOptions {
  int boxes = 150;
  uint64_t seed = 1;
};

// The room is [-3, 3] × [0, 3] × [-3, 3] (floor at y = 0), the light a 1 m square
// centred under the ceiling at kDenseLightY, facing down. Box i ("box_<i>",
// material "white" or "clay") has sides drawn from [kDenseMinSide, kDenseMaxSide]
// · (15 / boxes)^(1/3) independently, is turned by three random angles (x, y, z) and
// placed with its bounding sphere kDenseGap clear of the walls, the floor, the
// light's plane and every earlier box (so boxes never touch), filling the room
// alike at every count. Throws if a box cannot be placed.
inline constexpr double kDenseHalfSide = 3.0;
inline constexpr double kDenseHeight = 3.0;
inline constexpr double kDenseLightSide = 1.0;
inline constexpr double kDenseLightY = kDenseHeight - 1.0 / 64;
inline constexpr double kDenseMinSide = 0.1;
inline constexpr double kDenseMaxSide = 0.5;
inline constexpr double kDenseGap = 0.01;

Scene makeDenseScene(const DenseSceneOptions& options);

}  // namespace penumbra
