// Summing a point's per-light values into its irradiance and class, as the reference does.
// Free function on a const Scene; thread-safe.
#pragma once

#include <span>
#include <vector>

#include "core/illum/vertex_illumination.h"

namespace penumbra {

// Radiance-weighted factors, classes combined over the lights that reach the point (Umbra if
// none does). dark[l]: light l counts as in umbra (a cell in its umbra), adding nothing.
VertexIrradiance sumLights(const Scene& scene, std::span<const VertexLight> lights,
                           const std::vector<bool>* dark = nullptr);
// The same with each light's radiance given (radiance[l]), e.g. as it was before an edit.
VertexIrradiance sumLights(std::span<const Vec3> radiance, std::span<const VertexLight> lights);

}  // namespace penumbra
