// Test helper: models placed in the dense room (scenegen/dense_scene.h) under its ceiling
// light, moved off centre so no symmetry hides a mistake. Header-only; test use.
#pragma once

#include <vector>

#include "core/scene/scene.h"
#include "scenegen/dense_scene.h"
#include "scenegen/scene_parts.h"

namespace penumbra::testing {

inline Scene roomWith(std::vector<Object> models) {
  std::vector<Light> lights{squareCeilingLight("light", Vec3(0.2, kDenseLightY, -0.1), kDenseLightSide, 0, Vec3(1, 0, 0))};
  std::vector<Object> objects = roomObjects(kDenseHalfSide, kDenseHalfSide, kDenseHeight);
  for (Object& m : models) objects.push_back(std::move(m));
  return Scene(std::move(lights), {{"white", Vec3(0.8)}}, std::move(objects));
}

}  // namespace penumbra::testing
