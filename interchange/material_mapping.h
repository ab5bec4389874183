// How OBJ/MTL and glTF material parameters map onto Penumbra's microfacet materials
// (docs/SCENE_FORMAT.md "Materials"). Pure functions; thread-safe.
#pragma once

#include "core/scene/scene.h"

namespace penumbra::interchange {

// glTF / MTL "Pr" perceptual roughness r -> alpha = r² (clamped to the format's minimum).
double alphaFromPerceptual(double roughness);
// MTL Ns Phong exponent -> the Beckmann-equivalent alpha = sqrt(2 / (Ns + 2)) (Walter et al. 2007).
double alphaFromPhong(double exponent);
// A conductor whose normal-incidence reflectance is baseColor (edge tint = baseColor):
// Gulbrandsen 2014's artist-friendly mapping to eta, k.
void setConductorFromBaseColor(Material& material, const Vec3& baseColor);

}  // namespace penumbra::interchange
