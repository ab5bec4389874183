// The paper's octree volume (Knoll et al., Appendix A): interior nodes per depth holding their
// children's scalars, min/max pairs, a 32-bit child_start and a byte offset per child (−1 =
// scalar leaf); caps of 8 scalars at d_max − 1. Built once from a dense grid, then read-only:
// thread-safe to read. T is uint8_t, uint16_t or float (explicitly instantiated).
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/volume/dense_grid.h"

namespace penumbra::volume {

// The offset of child `child` (index x << 2 | y << 1 | z) from its parent's origin, in child sizes.
inline glm::ivec3 octant(int child) { return {(child >> 2) & 1, (child >> 1) & 1, child & 1}; }

template <class T>
struct OctNode {
  std::array<T, 8> childScalars{};  // the value of a scalar-leaf child (else its average)
  std::array<T, 8> childMins{};     // min/max over the child's cells (forward neighbours)
  std::array<T, 8> childMaxs{};
  uint32_t childStart = 0;              // first child in the next depth's array (or in caps)
  std::array<int8_t, 8> childOffset{};  // child index = childStart + offset; −1 = scalar leaf
};

template <class T>
struct OctCap {
  std::array<T, 8> scalars{};  // voxels at d_max, index x << 2 | y << 1 | z
};

struct OctreeBuildOptions {
  // 0: lossless (8 identical voxels consolidate). Above 0: 8 leaves whose population variance
  // is at most this consolidate into their average (lossy).
  double varianceThreshold = 0.0;
};

template <class T>
class OctreeVolume {
 public:
  static OctreeVolume build(const DenseGrid<T>& grid, const OctreeBuildOptions& options = {});

  // The voxel at p (point location from the root); 0 outside [0, 2^d_max)³.
  T voxel(glm::ivec3 p) const { return locateFrom(0, 0, p); }
  // Point location from a node known to contain p (depth, index): neighbour finding starts
  // at the nearest common ancestor instead of the root. 0 outside [0, 2^d_max)³.
  T locateFrom(int depth, uint32_t index, glm::ivec3 p) const;
  DenseGrid<T> decode() const;  // every voxel of the data extent

  glm::ivec3 dataSize() const { return size_; }
  int maxDepth() const { return maxDepth_; }  // d_max; the root covers 2^d_max voxels a side
  int side() const { return 1 << maxDepth_; }
  const std::vector<OctNode<T>>& nodes(int depth) const { return nodes_[depth]; }
  const std::vector<OctCap<T>>& caps() const { return caps_; }
  // The root block's min/max (the root has no parent to hold them).
  T rootMin() const { return rootMin_; }
  T rootMax() const { return rootMax_; }
  size_t bytes() const;  // nodes + caps, as stored
  size_t nodeCount() const;

  // Structural invariants: offsets inside the arrays, children packed, every node reached
  // once, min ≤ max. Throws std::logic_error naming the first broken one.
  void validate() const;

 private:
  glm::ivec3 size_{0};
  int maxDepth_ = 0;
  std::vector<std::vector<OctNode<T>>> nodes_;  // depths 0 … d_max − 2
  std::vector<OctCap<T>> caps_;                 // depth d_max − 1
  T rootMin_{}, rootMax_{};

  struct Built;
  Built buildBlock(const DenseGrid<T>& grid, const OctreeBuildOptions& options, int depth,
                   glm::ivec3 origin);
  std::array<T, 2> fillMinMax(const DenseGrid<T>& field, int depth, uint32_t index,
                              glm::ivec3 origin);
};

extern template class OctreeVolume<uint8_t>;
extern template class OctreeVolume<uint16_t>;
extern template class OctreeVolume<float>;

}  // namespace penumbra::volume
