#include "core/volume/octree_volume.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra::volume {

namespace {

// 8 values consolidate into one when identical (lossless) or, lossy, when their variance is
// at most the threshold; the result is their (rounded) mean.
template <class T>
bool consolidates(const std::array<T, 8>& v, double threshold, T& out) {
  if (threshold <= 0.0) {
    for (int i = 1; i < 8; ++i)
      if (!(v[i] == v[0])) return false;
    out = v[0];
    return true;
  }
  double mean = 0.0, square = 0.0;
  for (T x : v) mean += double(x) / 8.0;
  for (T x : v) square += (double(x) - mean) * (double(x) - mean) / 8.0;
  if (square > threshold) return false;
  out = std::is_floating_point_v<T> ? T(mean) : T(std::lround(mean));
  return true;
}

template <class T>
T meanOf(const std::array<T, 8>& v) {
  double mean = 0.0;
  for (T x : v) mean += double(x) / 8.0;
  return std::is_floating_point_v<T> ? T(mean) : T(std::lround(mean));
}

}  // namespace

template <class T>
struct OctreeVolume<T>::Built {
  bool leaf = true;
  T value{};  // the leaf's value, or the block's mean
  OctNode<T> node;
  OctCap<T> cap;
};

template <class T>
OctreeVolume<T> OctreeVolume<T>::build(const DenseGrid<T>& grid,
                                       const OctreeBuildOptions& options) {
  OctreeVolume out;
  out.size_ = grid.size;
  const int largest = std::max({grid.size.x, grid.size.y, grid.size.z});
  out.maxDepth_ = 2;  // at least a root node over caps
  while ((1 << out.maxDepth_) < largest) ++out.maxDepth_;
  if (out.maxDepth_ > 24) throw std::invalid_argument("volume too large for 32-bit octree indices");
  out.nodes_.resize(out.maxDepth_ - 1);
  Built root = out.buildBlock(grid, options, 0, glm::ivec3(0));
  out.nodes_[0].push_back(root.node);
  if (options.varianceThreshold > 0.0) {
    const DenseGrid<T> stored = out.decode();  // min/max must bound the stored field
    const auto range = out.fillMinMax(stored, 0, 0, glm::ivec3(0));
    out.rootMin_ = range[0], out.rootMax_ = range[1];
  } else {
    const auto range = out.fillMinMax(grid, 0, 0, glm::ivec3(0));
    out.rootMin_ = range[0], out.rootMax_ = range[1];
  }
  return out;
}

// Bottom-up consolidation: the 8 children are built first, then either merged into one
// scalar (a leaf in the parent) or stored contiguously one depth down.
template <class T>
typename OctreeVolume<T>::Built OctreeVolume<T>::buildBlock(const DenseGrid<T>& grid,
                                                            const OctreeBuildOptions& options,
                                                            int depth, glm::ivec3 origin) {
  Built out;
  if (depth > 0 && (origin.x >= size_.x || origin.y >= size_.y || origin.z >= size_.z))
    return out;  // wholly outside the data: a 0 leaf
  if (depth == maxDepth_ - 1) {
    for (int c = 0; c < 8; ++c) out.cap.scalars[c] = grid.at(origin + octant(c));
    out.leaf = consolidates(out.cap.scalars, options.varianceThreshold, out.value);
    if (!out.leaf) out.value = meanOf(out.cap.scalars);
    return out;
  }
  const int half = 1 << (maxDepth_ - depth - 1);
  std::array<Built, 8> children;
  bool allLeaves = true;
  for (int c = 0; c < 8; ++c) {
    children[c] = buildBlock(grid, options, depth + 1, origin + octant(c) * half);
    out.node.childScalars[c] = children[c].value;
    allLeaves = allLeaves && children[c].leaf;
  }
  if (depth > 0 && allLeaves &&
      consolidates(out.node.childScalars, options.varianceThreshold, out.value))
    return out;
  out.leaf = false;
  out.value = meanOf(out.node.childScalars);
  const bool childrenAreCaps = depth + 1 == maxDepth_ - 1;
  const size_t start = childrenAreCaps ? caps_.size() : nodes_[depth + 1].size();
  if (start > UINT32_MAX - 8) throw std::length_error("octree level exceeds 32-bit indices");
  out.node.childStart = uint32_t(start);
  int8_t next = 0;
  for (int c = 0; c < 8; ++c) {
    if (children[c].leaf) {
      out.node.childOffset[c] = -1;
      continue;
    }
    out.node.childOffset[c] = next++;
    if (childrenAreCaps)
      caps_.push_back(children[c].cap);
    else
      nodes_[depth + 1].push_back(children[c].node);
  }
  return out;
}

// The min/max tree: a child's pair covers every cell of its block, i.e. its voxels and their
// forward neighbours ((h + 1)³ voxels, 27 for a cap); parents combine their children's pairs.
template <class T>
std::array<T, 2> OctreeVolume<T>::fillMinMax(const DenseGrid<T>& field, int depth, uint32_t index,
                                             glm::ivec3 origin) {
  OctNode<T>& node = nodes_[depth][index];
  const int half = 1 << (maxDepth_ - depth - 1);
  std::array<T, 2> total{};
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 o = origin + octant(c) * half;
    std::array<T, 2> range{node.childScalars[c], node.childScalars[c]};
    auto take = [&](glm::ivec3 p) {
      const T v = field.at(p);
      range[0] = std::min(range[0], v);
      range[1] = std::max(range[1], v);
    };
    if (node.childOffset[c] >= 0 && depth + 1 < maxDepth_ - 1) {
      range = fillMinMax(field, depth + 1, node.childStart + node.childOffset[c], o);
    } else if (node.childOffset[c] >= 0) {  // a cap: its 27 voxels
      range = {field.at(o), field.at(o)};
      for (int z = 0; z <= 2; ++z)
        for (int y = 0; y <= 2; ++y)
          for (int x = 0; x <= 2; ++x) take(o + glm::ivec3(x, y, z));
    } else {  // a scalar leaf: uniform inside, so only its three forward faces matter
      for (int a = 0; a <= half; ++a)
        for (int b = 0; b <= half; ++b) {
          take(o + glm::ivec3(half, a, b));
          take(o + glm::ivec3(a, half, b));
          take(o + glm::ivec3(a, b, half));
        }
    }
    node.childMins[c] = range[0];
    node.childMaxs[c] = range[1];
    total = c == 0 ? range
                   : std::array<T, 2>{std::min(total[0], range[0]), std::max(total[1], range[1])};
  }
  return total;
}

// Point location (Appendix B.1): one octant per depth from the root.
template <class T>
T OctreeVolume<T>::locateFrom(int depth, uint32_t index, glm::ivec3 p) const {
  const int n = side();
  if (p.x < 0 || p.y < 0 || p.z < 0 || p.x >= n || p.y >= n || p.z >= n) return T(0);
  for (;; ++depth) {
    const OctNode<T>& node = nodes_[depth][index];
    const int bit = 1 << (maxDepth_ - depth - 1);
    const int child = ((p.x & bit) != 0) << 2 | ((p.y & bit) != 0) << 1 | int((p.z & bit) != 0);
    if (node.childOffset[child] < 0) return node.childScalars[child];
    index = node.childStart + uint32_t(node.childOffset[child]);
    if (depth == maxDepth_ - 2)
      return caps_[index].scalars[(p.x & 1) << 2 | (p.y & 1) << 1 | (p.z & 1)];
  }
}

template <class T>
DenseGrid<T> OctreeVolume<T>::decode() const {
  DenseGrid<T> out(size_);
  for (int z = 0; z < size_.z; ++z)
    for (int y = 0; y < size_.y; ++y)
      for (int x = 0; x < size_.x; ++x) out[{x, y, z}] = voxel({x, y, z});
  return out;
}

template <class T>
size_t OctreeVolume<T>::bytes() const {
  return nodeCount() * sizeof(OctNode<T>) + caps_.size() * sizeof(OctCap<T>);
}

template <class T>
size_t OctreeVolume<T>::nodeCount() const {
  size_t count = 0;
  for (const auto& level : nodes_) count += level.size();
  return count;
}

template <class T>
void OctreeVolume<T>::validate() const {
  auto fail = [](const std::string& what) { throw std::logic_error("OctreeVolume: " + what); };
  if (nodes_.size() != size_t(maxDepth_ - 1) || nodes_[0].size() != 1) fail("root level");
  for (int depth = 0; depth + 1 < maxDepth_; ++depth) {
    const size_t below = depth + 2 == maxDepth_ ? caps_.size() : nodes_[depth + 1].size();
    size_t expected = 0;  // children are packed in parent order, so starts run on
    for (const OctNode<T>& node : nodes_[depth]) {
      int8_t next = 0;
      for (int c = 0; c < 8; ++c) {
        if (node.childMins[c] > node.childMaxs[c])
          fail("min > max at depth " + std::to_string(depth));
        if (node.childOffset[c] < 0) continue;
        if (node.childOffset[c] != next++)
          fail("offsets not packed at depth " + std::to_string(depth));
      }
      if (next > 0 && node.childStart != expected)
        fail("child_start at depth " + std::to_string(depth));
      expected += size_t(next);
    }
    if (expected != below) fail("unreached or shared nodes below depth " + std::to_string(depth));
  }
}

template class OctreeVolume<uint8_t>;
template class OctreeVolume<uint16_t>;
template class OctreeVolume<float>;

}  // namespace penumbra::volume
