#include "core/illum/light_sum.h"

namespace penumbra {

namespace {

// radianceOf(l): light l's radiance. One loop for both entry points, so they sum alike.
template <typename RadianceOf>
VertexIrradiance sumWith(const RadianceOf& radianceOf, std::span<const VertexLight> lights,
                         const std::vector<bool>* dark) {
  VertexIrradiance out;
  bool any = false;
  for (size_t l = 0; l < lights.size(); ++l) {
    const VertexLight& light = lights[l];
    out.comparisons += light.comparisons();
    if (!light.applies()) continue;
    const bool isDark = dark && (*dark)[l];
    const LightClass cls = isDark ? LightClass::Umbra : light.lightClass();
    if (!isDark) out.irradiance += radianceOf(l) * light.factor();
    out.lightClass = any ? combine(out.lightClass, cls) : cls;
    any = true;
  }
  if (!any) out.lightClass = LightClass::Umbra;
  return out;
}

}  // namespace

VertexIrradiance sumLights(const Scene& scene, std::span<const VertexLight> lights,
                           const std::vector<bool>* dark) {
  return sumWith([&](size_t l) -> const Vec3& { return scene.lights()[l].radiance; }, lights, dark);
}

VertexIrradiance sumLights(std::span<const Vec3> radiance, std::span<const VertexLight> lights) {
  return sumWith([&](size_t l) -> const Vec3& { return radiance[l]; }, lights, nullptr);
}

}  // namespace penumbra
