// The graph method for the offending fragments sharing one cell of T' (paper §2.1):
// "A precedes B" edges decided with exact convex geometry, then a topological sort.
// Free functions on values; thread-safe.
#pragma once

#include <cstddef>
#include <vector>

#include "core/geom/plane.h"
#include "core/geom/polygon.h"
#include "core/geom/tolerance.h"
#include "core/scene/scene.h"

namespace penumbra {

// A piece of a face, with the face's plane (fragments of one face share it exactly).
struct PlanarFragment {
  FaceId face;
  Polygon3 polygon;
  Plane plane;
};

// Whether some ray from a point of `light` crosses `a` (through its front side) and
// then `b` (through its front side): the light points strictly in front of both
// planes, and part of b behind a's plane inside the penumbra volume of a from them.
// Exact for convex pieces up to eps (= tolerance.length()); never misses an order.
bool mayPrecede(const PlanarFragment& a, const PlanarFragment& b, const Polygon3& light,
                const Tolerance& tolerance);

struct OffendingOrder {
  std::vector<PlanarFragment> fragments;  // front to back
  size_t splits = 0;        // fragments split by a cycle member's plane to open cycles
  size_t cyclesBroken = 0;  // strongly connected groups ordered by the fallback rule
};

// Orders fragments front to back from `light`. A cycle of the precedence graph is
// opened by splitting its members by one member's plane (a piece in front of that
// plane never follows it, a piece behind never precedes it); a cycle that survives
// full mutual splitting is broken by taking its piece nearest the light first, and
// counted. Deterministic.
OffendingOrder sortOffending(std::vector<PlanarFragment> fragments, const Polygon3& light,
                             const Tolerance& tolerance);

}  // namespace penumbra
