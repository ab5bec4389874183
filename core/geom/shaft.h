// The shaft between two convex polygons (a light and a receiver): their convex hull, which
// holds every segment from a point of one to a point of the other, as inward half-spaces.
// Anything that shadows the receiver from the light meets such a segment, so it lies in the
// shaft; what lies well outside it casts nothing there (core/shadow/object_shadow.cpp culls a
// mesh's silhouette by it). Plain value; thread-safe.
#pragma once

#include <vector>

#include "core/geom/plane.h"
#include "core/geom/polygon.h"

namespace penumbra {

struct Shaft {
  // Inward: a point is inside when signedDistance ≥ 0 for every side (up to the tolerance the
  // sides were checked with). Empty: nothing is known, everything is inside.
  std::vector<Plane> sides;

  // The ball lies more than radius + margin outside some side.
  bool ballOutside(const Vec3& centre, double radius, double margin) const {
    for (const Plane& side : sides)
      if (side.signedDistance(centre) < -(radius + margin)) return true;
    return false;
  }
};

// The candidate sides of the hull of a and b (each polygon's own plane, and the planes through
// an edge of one and a corner of the other) kept only where every corner of both lies no more
// than eps outside, as computed with the side's own normal: the region is the hull or more,
// never less. Degenerate candidates (a zero normal) are dropped, which only enlarges it.
Shaft shaftBetween(const Polygon3& a, const Polygon3& b, double eps);

}  // namespace penumbra
