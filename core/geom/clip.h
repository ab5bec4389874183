// Clipping of convex 3D polygons by planes (Sutherland–Hodgman, one plane at a time).
// Free functions on values; thread-safe.
#pragma once

#include "core/geom/plane.h"
#include "core/geom/polygon.h"

namespace penumbra {

// The part of a convex polygon in front of `plane`. Vertices within eps of the
// plane count as on it and are kept unmoved; the result is empty unless some
// vertex lies more than eps in front (nothing of positive area remains), and
// the whole polygon is returned unchanged if no vertex lies more than eps behind.
Polygon3 clipFront(const Polygon3& polygon, const Plane& plane, double eps);
// The same into `out` (cleared first; its capacity is reused). `out` must not be `polygon`.
void clipFrontInto(const Polygon3& polygon, const Plane& plane, double eps, Polygon3& out);

// Both sides at once, sharing the cut points (so the two areas add up exactly).
struct Split3 {
  Polygon3 front, back;
};
Split3 splitByPlane(const Polygon3& polygon, const Plane& plane, double eps);

}  // namespace penumbra
