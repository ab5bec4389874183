#include "core/illum/light_sum.h"

namespace penumbra {

VertexIrradiance sumLights(const Scene& scene, std::span<const VertexLight> lights,
                           const std::vector<bool>* dark) {
  VertexIrradiance out;
  bool any = false;
  for (size_t l = 0; l < lights.size(); ++l) {
    const VertexLight& light = lights[l];
    out.comparisons += light.comparisons;
    if (!light.applies) continue;
    const bool isDark = dark && (*dark)[l];
    const LightClass cls = isDark ? LightClass::Umbra : light.lightClass;
    if (!isDark) out.irradiance += scene.lights()[l].radiance * light.factor;
    out.lightClass = any ? combine(out.lightClass, cls) : cls;
    any = true;
  }
  if (!any) out.lightClass = LightClass::Umbra;
  return out;
}

}  // namespace penumbra
