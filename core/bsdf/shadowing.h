// Shadowing-masking of a Smith microsurface over the full sphere (seed 004 eqs. 3, 12, 17) and the
// walk's height models. Pure functions; thread-safe.
#pragma once

#include "core/bsdf/microsurface.h"

namespace penumbra::bsdf {

enum class HeightModel { Uncorrelated, Correlated };

// Directions point away from the microsurface point: wi towards where the light came from
// (below the macrosurface when the ray arrived travelling upwards), wo where it leaves.
// Height-uncorrelated G2 = G1(wi) G1(wo), each of eq. 3.
double g2Uncorrelated(const Microsurface& s, const Vec3& wi, const Vec3& wo);
// Height-correlated G2 for the last bounce (eq. 12): 1/(1 + Λ(wi) + Λ(wo)) when wi is above,
// 1/(Λ(-wi) + Λ(wo)) when wi is below. wo above the macrosurface.
double g2Correlated(const Microsurface& s, const Vec3& wi, const Vec3& wo);
// Middle bounce (eq. 17): the light arrives from wi and the ray leaving along wo is blocked. Exact
// only at a walk's first vertex: eq. 15 weights heights by P1(h) G1(wi, h), the heights where a
// ray from outside lands; a later vertex lies where the previous ray was blocked (vertex_height.h).
double g2Middle(const Microsurface& s, const Vec3& wi, const Vec3& wo);

}  // namespace penumbra::bsdf
