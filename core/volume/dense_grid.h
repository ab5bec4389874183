// A dense scalar grid (uint8, uint16 or float voxels, x fastest): the input the octree is
// built from and the raw array the macrocell baseline traces. Plain value; thread-safe to read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <stdexcept>
#include <vector>

namespace penumbra::volume {

template <class T>
struct DenseGrid {
  glm::ivec3 size{0};
  std::vector<T> values;  // size.x * size.y * size.z, index x + size.x * (y + size.y * z)

  DenseGrid() = default;
  explicit DenseGrid(glm::ivec3 dims) : size(dims) {
    if (dims.x < 2 || dims.y < 2 || dims.z < 2) throw std::invalid_argument("grid side < 2");
    values.assign(size_t(dims.x) * size_t(dims.y) * size_t(dims.z), T(0));
  }

  bool inside(glm::ivec3 p) const {
    return p.x >= 0 && p.y >= 0 && p.z >= 0 && p.x < size.x && p.y < size.y && p.z < size.z;
  }
  size_t index(glm::ivec3 p) const {
    return size_t(p.x) + size_t(size.x) * (size_t(p.y) + size_t(size.y) * size_t(p.z));
  }
  // The voxel at p; outside the grid the field is 0 (the paper's convention).
  T at(glm::ivec3 p) const { return inside(p) ? values[index(p)] : T(0); }
  T& operator[](glm::ivec3 p) { return values[index(p)]; }
  size_t bytes() const { return values.size() * sizeof(T); }
};

}  // namespace penumbra::volume
