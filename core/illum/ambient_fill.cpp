#include "core/illum/ambient_fill.h"

#include <cmath>

namespace penumbra {

Vec3 ambientIrradiance(const Scene& scene, double fraction) {
  Vec3 power(0.0);
  for (const Light& light : scene.lights()) power += M_PI * light.radiance * light.area();
  const Vec3 e = scene.bounds().max - scene.bounds().min;
  const double surface = 2 * (e.x * e.y + e.y * e.z + e.z * e.x);
  if (!(surface > 0)) return Vec3(0.0);
  return fraction * power / surface;
}

}  // namespace penumbra
