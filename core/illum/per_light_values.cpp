#include "core/illum/per_light_values.h"

#include <algorithm>

namespace penumbra {

void PerLightValues::assign(size_t slots, size_t lights) {
  lights_ = lights;
  slots_ = slots;
  data_.assign(slots * lights, VertexLight{});
}

void PerLightValues::resize(size_t slots, size_t lights) {
  if (lights == lights_) {
    slots_ = slots;
    data_.resize(slots * lights);
    return;
  }
  std::vector<VertexLight> rows(slots * lights);
  const size_t keptRows = std::min(slots, size()), keptLights = std::min(lights, lights_);
  for (size_t s = 0; s < keptRows; ++s)
    std::copy_n(data_.begin() + std::ptrdiff_t(s * lights_), keptLights, rows.begin() + std::ptrdiff_t(s * lights));
  data_ = std::move(rows);
  lights_ = lights;
  slots_ = slots;
}

}  // namespace penumbra
