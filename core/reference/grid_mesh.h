// The baseline mesh: every receiving face split into an N×N-ish grid of
// triangles whose vertex values come from the exact reference.
#pragma once

#include <functional>

#include "core/mesh/mesh.h"
#include "core/scene/scene.h"

namespace penumbra {

// Called with (points done, points in all) as the work proceeds; may be empty.
using ProgressCallback = std::function<void(size_t done, size_t total)>;

Mesh referenceGridMesh(const Scene& scene, int gridSize, const ProgressCallback& progress = {});

}  // namespace penumbra
