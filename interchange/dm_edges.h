// The discontinuity edges of a built engine as world-space segments (every cell
// edge of every receiver's DM-tree, once), for the GLB's line primitive.
// Free function over const engine state; thread-safe with other readers.
#pragma once

#include <vector>

#include "core/engine/engine.h"
#include "interchange/glb_export.h"

namespace penumbra::interchange {

std::vector<Segment3> dmEdges(const Engine& engine);

}  // namespace penumbra::interchange
