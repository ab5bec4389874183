// Every vertex slot's per-light values (VertexLight), one row of lightCount() entries per slot
// in one array: a vector per vertex cost a heap block and ~32 bytes more each. Plain data; one
// writer per slot at a time.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/illum/vertex_illumination.h"

namespace penumbra {

class PerLightValues {
 public:
  // `slots` rows of `lights` default entries (a default entry does not apply: no light).
  void assign(size_t slots, size_t lights);
  // Grows or shrinks to `slots` rows of `lights` entries; rows kept keep their first entries.
  void resize(size_t slots, size_t lights);
  // Room for `slots` rows of `lights` entries.
  void reserve(size_t slots, size_t lights) { data_.reserve(slots * lights); }

  size_t size() const { return lights_ ? data_.size() / lights_ : slots_; }
  size_t lightCount() const { return lights_; }
  std::span<VertexLight> operator[](size_t slot) { return {data_.data() + slot * lights_, lights_}; }
  std::span<const VertexLight> operator[](size_t slot) const { return {data_.data() + slot * lights_, lights_}; }

 private:
  size_t lights_ = 0;
  size_t slots_ = 0;  // the row count when there are no lights
  std::vector<VertexLight> data_;
};

}  // namespace penumbra
