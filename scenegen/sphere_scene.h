// Generator of the one-sphere scene: a UV sphere of about N faces floating in the dense
// room (scenegen/dense_scene.h) under its 1 m² ceiling light. Pure; thread-safe.
#pragma once

#include "core/scene/scene.h"

namespace penumbra {

struct SphereSceneOptions {
  int faces = 1152;      // asked for; the sphere has uvSphereGrid(faces) stacks × slices
  double radius = 0.35;  // metres
  Vec3 centre{0.0, 1.0, 0.0};
};

// Stacks and slices of a UV sphere of about `faces` faces, twice as many slices as
// stacks: stacks = round(√(faces / 2)) (≥ 2), slices = round(faces / stacks) (≥ 3).
// 1152 → 24 × 48 (exact); faces = stacks · slices.
struct UvSphereGrid {
  int stacks = 2, slices = 3;
};
UvSphereGrid uvSphereGrid(int faces);

// The room [-3, 3] × [0, 3] × [-3, 3] ("floor", "ceiling", "wall_*") and one object
// "sphere" (material "clay"): triangles round the poles, planar quads between, all
// outward — a closed convex object. Throws std::invalid_argument for faces < 6 or
// a sphere reaching outside the room.
Scene makeSphereScene(const SphereSceneOptions& options);

}  // namespace penumbra
