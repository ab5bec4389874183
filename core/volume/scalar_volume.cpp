#include "core/volume/scalar_volume.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/volume/octree_trace.h"

namespace penumbra::volume {

template <class T>
ScalarVolume::ScalarVolume(const DenseGrid<T>& grid, const Mat3& objectFromVoxel)
    : octree_(OctreeVolume<T>::build(grid)), size_(grid.size), objectFromVoxel_(objectFromVoxel) {
  const double det = glm::determinant(objectFromVoxel);
  if (!std::isfinite(det) || det == 0.0)
    throw std::invalid_argument("volume: the voxel-to-object map is singular");
  const auto [lo, hi] = std::minmax_element(grid.values.begin(), grid.values.end());
  min_ = double(*lo);
  max_ = double(*hi);
}

template ScalarVolume::ScalarVolume(const DenseGrid<uint8_t>&, const Mat3&);
template ScalarVolume::ScalarVolume(const DenseGrid<uint16_t>&, const Mat3&);
template ScalarVolume::ScalarVolume(const DenseGrid<float>&, const Mat3&);

std::optional<VolumeHit> ScalarVolume::trace(const VolumeRay& ray, double isovalue) const {
  return std::visit([&](const auto& octree) { return traceOctree(octree, ray, isovalue); },
                    octree_);
}

double ScalarVolume::voxel(glm::ivec3 p) const {
  return std::visit([&](const auto& octree) { return double(octree.voxel(p)); }, octree_);
}

std::string ScalarVolume::typeName() const {
  static const char* const kNames[] = {"uchar", "ushort", "float"};
  return kNames[octree_.index()];
}

size_t ScalarVolume::bytes() const {
  return std::visit([](const auto& octree) { return octree.bytes(); }, octree_);
}

}  // namespace penumbra::volume
