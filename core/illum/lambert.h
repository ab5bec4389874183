// Lambert's exact polygon formula: the irradiance integral of a uniform planar
// polygon seen from a point. Free function; thread-safe.
#pragma once

#include "core/geom/polygon.h"
#include "core/geom/vec.h"

namespace penumbra {

// ∫ cosθp·cosθL / r² dA over `polygon` (convex or not, either winding) seen from p
// with unit normal n; the polygon must lie in front of p's plane. Equals π × the
// point-to-polygon form factor.
double lambertIntegral(const Vec3& p, const Vec3& n, const Polygon3& polygon);

// One edge's term of Lambert's sum, Θ (n · Γ) with Θ the angle a→b subtends at p and
// Γ the unit normal of the plane through p, a and b (signed by the direction a→b).
// Additive along a line: the terms of a→m and m→b add up to that of a→b, so the
// integral over a region is half the sum over any split of its boundary.
double lambertEdgeTerm(const Vec3& p, const Vec3& n, const Vec3& a, const Vec3& b);

}  // namespace penumbra
