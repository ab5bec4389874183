// Further subdivision of DM cells for display (paper §4: "further triangulation"):
// a convex cell is cut by the lines x = k·spacing and y = k·spacing of its face's
// 2D frame. The lines are the same for every cell of a face, so neighbouring cells
// are cut at the same points of their shared edges (no T-junctions).
// Pure function; thread-safe.
#pragma once

#include <vector>

#include "core/geom/convex2d.h"

namespace penumbra {

// The convex pieces of `cell` (CCW) between consecutive lattice lines. Vertices
// within eps of a line count as on it (no sliver pieces). spacing <= 0: {cell}.
std::vector<Polygon2> splitByLattice(const Polygon2& cell, double spacing, double eps);

}  // namespace penumbra
