#include "interchange/material_mapping.h"

#include <algorithm>
#include <cmath>

namespace penumbra::interchange {

double alphaFromPerceptual(double roughness) { return std::clamp(roughness * roughness, 1e-3, 2.0); }

double alphaFromPhong(double exponent) { return std::clamp(std::sqrt(2.0 / (std::max(exponent, 0.0) + 2.0)), 1e-3, 2.0); }

void setConductorFromBaseColor(Material& material, const Vec3& baseColor) {
  material.type = MaterialType::Conductor;
  for (int c = 0; c < 3; ++c) {
    const double r = std::clamp(baseColor[c], 0.0, 0.99), g = r;
    const double sr = std::sqrt(r);
    const double n = g * (1 - r) / (1 + r) + (1 - g) * (1 + sr) / (1 - sr);
    const double k2 = (r * (n + 1) * (n + 1) - (n - 1) * (n - 1)) / (1 - r);
    material.eta[c] = std::max(n, 1e-3);
    material.k[c] = std::sqrt(std::max(k2, 0.0));
  }
}

}  // namespace penumbra::interchange
