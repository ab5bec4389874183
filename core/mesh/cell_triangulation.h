// Triangulating one convex DM-tree cell whose boundary may hold collinear
// vertices (T-junction-free meshes put neighbours' vertices on straight sides).
// Pure function; thread-safe.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/geom/convex2d.h"

namespace penumbra {

struct CellTriangulation {
  // Indices into the loop; index loop.size() means the added centre point.
  std::vector<std::array<uint32_t, 3>> triangles;
  bool usesCentre = false;  // a centre vertex (the loop's vertex average) was needed
};

// A fan from a strictly convex corner whose two sides hold no other loop vertex
// (no zero-area triangles); if every corner has such a side, a fan from the centre.
// Triangles are counter-clockwise like the loop.
CellTriangulation triangulateConvexCell(const Polygon2& loop, double eps);

}  // namespace penumbra
