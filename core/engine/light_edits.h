// Light edits of a frame (Edit::Op::SetLight): what a frame does to the lights, the checks
// a set_light must pass, and the overlap cubes the lights span afterwards. Free functions
// on const data; thread-safe.
#pragma once

#include <vector>

#include "core/engine/frame.h"
#include "core/overlap/overlap_cube.h"
#include "core/scene/scene.h"

namespace penumbra {

// Whether the frame gives some light a new polygon (moved, resized, turned).
bool movesLight(const Frame& frame);
// Whether the frame gives some light a new radiance.
bool changesRadiance(const Frame& frame);

// The light a set_light edit leaves: `light` with the edit's polygon and/or radiance.
Light editedLight(const Light& light, const Edit& edit);

// Checks set_light edit `index` against `lights` (the scene's, as the frame's earlier
// edits leave them) and applies it there. Throws EditError naming the key path: "id"
// (unknown light), "" (neither polygon nor radiance), "polygon" (Scene::lightProblem, or
// a vertex outside the edit volume: the scene's bounds grown by the overlap cubes'
// margin), "radiance" (Scene::radianceProblem).
void checkLightEdit(const Scene& scene, const Edit& edit, size_t index, std::vector<Light>& lights);

// The lights after the frame's valid set_light edits (invalid ones are skipped: the
// check refuses them in order).
std::vector<Light> lightsAfter(const Scene& scene, const Frame& frame);

// The cube each light's OverlapCube spans for these lights (the engine's default settings).
std::vector<OverlapCube::Box> cubesFor(const Scene& scene, const std::vector<Light>& lights);

// Whether every vertex of the polygon lies in each cube (within the scene's length tolerance).
bool insideCubes(const Scene& scene, const Polygon3& polygon,
                 const std::vector<OverlapCube::Box>& cubes);

}  // namespace penumbra
