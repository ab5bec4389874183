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

}  // namespace penumbra
