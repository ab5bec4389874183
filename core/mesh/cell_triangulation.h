// Triangulating one convex DM-tree cell whose boundary may hold collinear
// vertices (T-junction-free meshes put neighbours' vertices on straight sides).
// Pure functions; thread-safe.
#pragma once

#include <array>
#include <cstdint>

#include "core/geom/convex2d.h"

namespace penumbra {

// A cell's triangles as one fan, so a word describes them all (the mesh memo keeps it
// instead of the triangles): from a loop corner, or from an added centre point. A piece
// refined further (core/mesh/cell_refinement.h) lists its triangles instead: the word then
// says where they end in the memo's list (kListed | end).
struct CellFan {
  static constexpr uint32_t kCentre = 0xffffffffu, kListed = 0x80000000u;
  uint32_t apex = 0;  // the loop index of the fan's corner, kCentre, or kListed | end
  bool usesCentre() const { return apex == kCentre; }
  bool listed() const { return apex != kCentre && (apex & kListed) != 0; }
  uint32_t listedEnd() const { return apex & ~kListed; }
  static CellFan listedUpTo(uint32_t end) { return CellFan{kListed | end}; }
  // The triangle count for a loop of n vertices (none below three).
  uint32_t triangleCount(uint32_t n) const;
  // Triangle k (< triangleCount(n)) as loop indices, counter-clockwise like the loop;
  // index n is the centre point.
  std::array<uint32_t, 3> triangle(uint32_t n, uint32_t k) const;
};

// A fan from a strictly convex corner whose two sides hold no other loop vertex
// (no zero-area triangles); if every corner has such a side, a fan from the centre
// (the loop's vertex average).
CellFan fanOfConvexCell(const Polygon2& loop, double eps);

// The loop's vertex average: the centre a fan from kCentre uses.
Vec2 vertexAverage(const Polygon2& loop);
// Whether the polygon's width (twice its area over its longest side) is below `width`: a
// sliver, whose points the mesh builder may merge with its neighbours' (within eps), which
// would fold triangles refined inside it. It keeps its fan.
bool narrowerThan(const Polygon2& polygon, double width);

}  // namespace penumbra
