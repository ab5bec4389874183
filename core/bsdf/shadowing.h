// Shadowing-masking of a Smith microsurface over the full sphere (seed 004 eqs. 3, 12, 17) and the
// escape probabilities of the position-free random walk built on them. Pure functions; thread-safe.
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
// Middle bounce (eq. 17): the light arrives from wi and the ray leaving along wo is blocked.
double g2Middle(const Microsurface& s, const Vec3& wi, const Vec3& wo);

// Probability that a ray leaving a microfacet along d escapes the microsurface, given that the
// light arrived at the facet from w (both in the frame of the side the ray is on, +z pointing
// into that side's medium). 0 when d points into the surface. Correlated: G2(w, d) / G1(w).
double escapeReflected(const Microsurface& s, HeightModel model, const Vec3& w, const Vec3& d);
// The same for a ray refracted to the other side, d given in that side's frame (the frame
// mirrored through the origin). Correlated: the hit height implied by eq. 12, x = C1(h) with
// density c x^(c-1), c = 1/G1(w), escapes downwards with probability (1 - x)^Λ(d), so
// c B(c, 1 + Λ(d)); at the first bounce this is the exact height-correlated transmission.
double escapeTransmitted(const Microsurface& s, HeightModel model, const Vec3& w, const Vec3& d);

}  // namespace penumbra::bsdf
