// Welding coincident vertices of one polygon soup (duplicate coordinates in real
// files): each position maps to the first one within eps of it. Free function; thread-safe.
#pragma once

#include <vector>

#include "core/geom/vec.h"

namespace penumbra::interchange {

struct WeldResult {
  std::vector<Vec3> positions;  // the distinct positions, in first-seen order
  std::vector<int> remap;       // input index → index into positions
  size_t merged = 0;            // input positions that joined an earlier one
};

// eps > 0: positions closer than eps (per coordinate) are one vertex.
WeldResult weldVertices(const std::vector<Vec3>& positions, double eps);

}  // namespace penumbra::interchange
