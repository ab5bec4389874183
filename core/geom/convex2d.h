// Convex polygons in a 2D plane frame: area, half-plane clipping, intersection,
// difference as disjoint convex pieces, containment. Free functions; thread-safe.
#pragma once

#include <span>
#include <vector>

#include "core/geom/vec.h"

namespace penumbra {

// Vertices in order; the operations below expect convex polygons, counter-clockwise
// unless a function says otherwise.
using Polygon2 = std::vector<Vec2>;

// Positive for counter-clockwise polygons.
double signedArea(std::span<const Vec2> polygon);
inline double signedArea(const Polygon2& polygon) { return signedArea(std::span<const Vec2>(polygon)); }
// The same polygon, counter-clockwise.
Polygon2 counterClockwise(Polygon2 polygon);

// Drops vertices within eps of their predecessor: a near-zero edge has no
// reliable direction, and its neighbours bound the polygon to within ~eps.
Polygon2 withoutDuplicateVertices(const Polygon2& polygon, double eps);

// Whether boxes [minA, maxA] and [minB, maxB] are more than eps apart along some axis.
inline bool boxesApart(const Vec2& minA, const Vec2& maxA, const Vec2& minB, const Vec2& maxB, double eps) {
  return minA.x > maxB.x + eps || minB.x > maxA.x + eps || minA.y > maxB.y + eps || minB.y > maxA.y + eps;
}

// Signed distance of p from the directed line a→b (positive on its left).
double lineDistance(const Vec2& a, const Vec2& b, const Vec2& p);

// The part of a convex polygon left of the directed line a→b. Vertices within eps
// of the line count as on it; empty unless some vertex lies more than eps to the left.
Polygon2 clipLeftOf(const Polygon2& polygon, const Vec2& a, const Vec2& b, double eps);

// Both sides at once, sharing the cut points so their areas add up to the whole.
struct Split2 {
  Polygon2 left, right;
};
Split2 splitByLine(const Polygon2& polygon, const Vec2& a, const Vec2& b, double eps);

// A ∩ B for convex CCW polygons; empty if it has no positive area (at eps).
Polygon2 intersect(const Polygon2& a, const Polygon2& b, double eps);

// A minus B as disjoint convex pieces (at most one per edge of B):
// area(A) = area(A ∩ B) + Σ area(pieces), up to slivers thinner than eps.
// Returns {A} unchanged if A ∩ B has no positive area; `overlapped` (optional) says
// whether anything was removed.
std::vector<Polygon2> subtract(const Polygon2& a, const Polygon2& b, double eps,
                               bool* overlapped = nullptr);
// A minus the union of the Bs: the fold of subtract over the Bs.
std::vector<Polygon2> subtract(const Polygon2& a, const std::vector<Polygon2>& bs, double eps,
                               bool* overlapped = nullptr);

// The area centroid of a polygon with positive area (relative to its first vertex:
// less cancellation far from the origin).
Vec2 areaCentroid(const Polygon2& polygon);

// Whether p lies in the convex CCW polygon or within eps of it.
bool contains(const Polygon2& polygon, const Vec2& p, double eps);

}  // namespace penumbra
