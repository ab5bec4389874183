// A scene volume's data: an octree volume of uint8, uint16 or float voxels (one of the three,
// chosen by the file) and where its voxels sit in object space (voxel i at objectFromVoxel·i,
// from the file's spacings or space directions). Built once, then read-only: thread-safe.
#pragma once

#include <optional>
#include <string>
#include <variant>

#include "core/geom/vec.h"
#include "core/volume/octree_volume.h"
#include "core/volume/volume_ray.h"

namespace penumbra::volume {

class ScalarVolume {
 public:
  // objectFromVoxel must be invertible (the reader checks it; std::invalid_argument if not).
  template <class T>
  ScalarVolume(const DenseGrid<T>& grid, const Mat3& objectFromVoxel);

  // The first isosurface hit of a voxel-space ray (t as the ray's), or nullopt.
  std::optional<VolumeHit> trace(const VolumeRay& ray, double isovalue) const;

  double voxel(glm::ivec3 p) const;  // the stored value; 0 outside the grid
  glm::ivec3 size() const { return size_; }
  const Mat3& objectFromVoxel() const { return objectFromVoxel_; }
  // "uchar", "ushort" or "float" (the NRRD type names).
  std::string typeName() const;
  double minValue() const { return min_; }
  double maxValue() const { return max_; }
  size_t bytes() const;  // the octree, as stored

 private:
  std::variant<OctreeVolume<uint8_t>, OctreeVolume<uint16_t>, OctreeVolume<float>> octree_;
  glm::ivec3 size_{0};
  Mat3 objectFromVoxel_{1.0};
  double min_ = 0, max_ = 0;
};

}  // namespace penumbra::volume
