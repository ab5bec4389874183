// Fresnel reflectance of a dielectric interface and of a conductor (complex IOR), and the
// mirror / refraction directions about a microfacet normal. Pure functions; thread-safe.
#pragma once

#include <optional>

#include "core/bsdf/microsurface.h"

namespace penumbra::bsdf {

// Unpolarised reflectance for light arriving at cosine cosI (> 0) from the side of index etaI
// onto the side of index etaT; eta = etaT / etaI. 1 under total internal reflection.
double fresnelDielectric(double cosI, double eta);
// Unpolarised reflectance of a conductor with complex index eta + i k (relative to the outside).
double fresnelConductor(double cosI, double eta, double k);
Vec3 fresnelConductor(double cosI, const Vec3& eta, const Vec3& k);

// w and the result point away from the surface point.
inline Vec3 reflect(const Vec3& w, const Vec3& m) { return 2.0 * glm::dot(w, m) * m - w; }
// Refraction of w (w·m > 0) through m with eta = etaT / etaI; the result points into the
// other medium (·m < 0); nothing under total internal reflection.
std::optional<Vec3> refract(const Vec3& w, const Vec3& m, double eta);

}  // namespace penumbra::bsdf
