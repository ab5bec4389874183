// The paper's comparison baseline (Parker et al.): a grid of macrocells, each holding the
// min/max over its cells' corners, traced with a two-level DDA over the raw dense array.
// One level of macrocells, not Parker's hierarchy (see DESIGN.md "Volumes"). Keeps a
// reference to the grid, which must outlive it; read-only after build: thread-safe to trace.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "core/volume/dense_grid.h"
#include "core/volume/octree_trace.h"
#include "core/volume/volume_ray.h"

namespace penumbra::volume {

template <class T>
class MacrocellGrid {
 public:
  MacrocellGrid(const DenseGrid<T>& grid, int cellsPerMacrocell = 8);

  // Same contract as traceOctree: first hit in the box [0, size − 1]³.
  std::optional<VolumeHit> trace(const VolumeRay& ray, double isovalue,
                                 TraceCounters* counters = nullptr) const;

  int macrocellSide() const { return side_; }
  size_t bytes() const { return ranges_.size() * sizeof(ranges_[0]); }  // beyond the grid

 private:
  const DenseGrid<T>& grid_;
  int side_;
  glm::ivec3 count_;                      // macrocells per axis
  std::vector<std::array<T, 2>> ranges_;  // min, max per macrocell, x fastest
};

extern template class MacrocellGrid<uint8_t>;
extern template class MacrocellGrid<uint16_t>;
extern template class MacrocellGrid<float>;

}  // namespace penumbra::volume
