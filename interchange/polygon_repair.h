// Turning one input polygon of a real file into faces the scene contract accepts:
// repeated vertices dropped, non-planar or non-convex polygons split into planar
// convex pieces (ear clipping, then joining pieces back while they stay planar and
// convex). Free functions over index polygons; thread-safe.
#pragma once

#include <vector>

#include "core/geom/vec.h"

namespace penumbra::interchange {

using IndexPolygon = std::vector<int>;

struct PolygonRepair {
  // Convex planar pieces, wound like the input (counter-clockwise about its Newell
  // normal); the input itself when it was already fine.
  std::vector<IndexPolygon> pieces;
  size_t repeatedVerticesRemoved = 0;  // consecutive repeats (same index or same position)
  bool degenerate = false;        // dropped: < 3 distinct vertices or zero area
  bool nonPlanar = false;         // split (planarity beyond SCENE_FORMAT's 1e-6)
  bool nonConvex = false;         // split
  bool selfIntersecting = false;  // dropped: no ear to clip
};

// `positions` are welded (equal positions have equal indices, except within eps of
// tolerance); indices must be valid.
PolygonRepair repairPolygon(const std::vector<Vec3>& positions, const IndexPolygon& polygon);

// Greedily joins pieces sharing an edge (a→b in one, b→a in the other) while the
// union is coplanar (1e-9 of its size) and convex, like Hertel–Mehlhorn. Returns
// how many joins it made; `pieces` keeps the survivors. `joinedInto` (optional): for
// each input piece, the index of the survivor that holds it.
size_t joinCoplanarConvex(const std::vector<Vec3>& positions, std::vector<IndexPolygon>& pieces,
                          std::vector<size_t>* joinedInto = nullptr);

}  // namespace penumbra::interchange
