// The flat ambient fill the renderer and exports add where no bounced light is computed, so
// a face in umbra is dim rather than black: a fraction of the lights' total emitted power
// spread over the surface of the scene's bounding box (W·m⁻² per channel). Display only; the
// exact irradiance never includes it. Pure function; thread-safe.
#pragma once

#include "core/scene/scene.h"

namespace penumbra {

inline constexpr double kDefaultAmbientFraction = 0.1;

Vec3 ambientIrradiance(const Scene& scene, double fraction = kDefaultAmbientFraction);

}  // namespace penumbra
