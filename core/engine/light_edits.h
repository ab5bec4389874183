// Light edits of a frame (set_light, add_light, remove_light): what a frame does to the
// lights, the checks each must pass, and the overlap cubes the lights span afterwards.
// Free functions on const data (applyLightEdit: on the scene it is given); thread-safe.
#pragma once

#include <vector>

#include "core/engine/frame.h"
#include "core/overlap/overlap_cube.h"
#include "core/scene/scene.h"

namespace penumbra {

// Whether the edit is a light's (set_light, add_light, remove_light).
bool isLightEdit(const Edit& edit);
// Whether the frame changes the lights' geometry: gives some light a new polygon (moved,
// resized, turned), adds or removes a light. Such a frame is a counted full rebuild.
bool reshapesLights(const Frame& frame);
// Whether the frame gives some light a new radiance.
bool changesRadiance(const Frame& frame);

// The light a set_light edit leaves: `light` with the edit's polygon and/or radiance.
Light editedLight(const Light& light, const Edit& edit);

// Checks light edit `index` against `lights` (the scene's, as the frame's earlier edits
// leave them) and applies it there. Throws EditError naming the key path.
// set_light: "id" (unknown light), "" (neither polygon nor radiance), "polygon"
// (Scene::lightProblem), "polygon[k]" (a vertex outside the edit volume: the scene's
// bounds grown by the overlap cubes' margin), "radiance" (Scene::radianceProblem).
// add_light: the same under "light." ("light.polygon", "light.polygon[k]",
// "light.radiance"), and "light.id" for an id some light has.
// remove_light: "id" (unknown light, or the last one: a scene keeps at least one).
void checkLightEdit(const Scene& scene, const Edit& edit, size_t index, std::vector<Light>& lights);

// Applies a checked light edit to the scene (Scene::setLight / addLight / removeLight).
void applyLightEdit(Scene& scene, const Edit& edit);

// The lights after the frame's valid light edits (invalid ones are skipped: the check
// refuses them in order).
std::vector<Light> lightsAfter(const Scene& scene, const Frame& frame);

// The cube each light's OverlapCube spans for these lights (the engine's default settings).
std::vector<OverlapCube::Box> cubesFor(const Scene& scene, const std::vector<Light>& lights);

// Whether every vertex of the polygon lies in each cube (within the scene's length tolerance).
bool insideCubes(const Scene& scene, const Polygon3& polygon,
                 const std::vector<OverlapCube::Box>& cubes);

}  // namespace penumbra
