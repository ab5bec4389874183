// The octree volume: every voxel back bit for bit (every generator, 8/16-bit and float, odd
// sizes), structure validity, and the min/max tree against brute force over the dense grid
// (never rejects a block holding the isovalue). Seeded.
#include "core/volume/octree_volume.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "scenegen/volume_fields.h"

namespace penumbra {
namespace {

using volume::DenseGrid;
using volume::OctreeVolume;

template <class T>
void expectRoundTrip(const DenseGrid<T>& grid, const std::string& what) {
  const OctreeVolume<T> octree = OctreeVolume<T>::build(grid);
  EXPECT_NO_THROW(octree.validate()) << what;
  size_t wrong = 0;
  for (int z = 0; z < grid.size.z; ++z)
    for (int y = 0; y < grid.size.y; ++y)
      for (int x = 0; x < grid.size.x; ++x) {
        const T want = grid.values[size_t(x) + size_t(grid.size.x) * (y + size_t(grid.size.y) * z)];
        const T got = octree.voxel({x, y, z});
        if (std::memcmp(&want, &got, sizeof(T)) != 0) ++wrong;
      }
  EXPECT_EQ(wrong, 0u) << what;
  // Outside the data the field is 0.
  EXPECT_EQ(octree.voxel(grid.size), T(0)) << what;
  EXPECT_EQ(octree.voxel({-1, 0, 0}), T(0)) << what;
}

TEST(OctreeVolume, LosslessRoundTripEveryGenerator) {
  const glm::ivec3 sizes[] = {{32, 32, 32}, {33, 17, 29}, {5, 3, 7}, {2, 2, 2}, {65, 40, 3}};
  for (VolumeField field : kVolumeFields)
    for (const glm::ivec3& size : sizes) {
      const DenseGrid<float> f = makeVolumeField({field, size, 7});
      const std::string what = volumeFieldName(field) + " " + std::to_string(size.x) + "x" +
                               std::to_string(size.y) + "x" + std::to_string(size.z);
      expectRoundTrip(quantise8(f), what + " 8-bit");
      expectRoundTrip(quantise16(f), what + " 16-bit");
      expectRoundTrip(f, what + " float");
    }
}

TEST(OctreeVolume, LosslessRoundTripRandomBlocks) {
  // Piecewise-constant random blocks of random sizes: consolidation at every depth.
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const glm::ivec3 size(2 + rng() % 40, 2 + rng() % 40, 2 + rng() % 40);
    DenseGrid<uint8_t> grid(size);
    const int block = 1 << (rng() % 4);
    for (int z = 0; z < size.z; ++z)
      for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
          const uint64_t key = uint64_t(x / block) * 73856093u ^ uint64_t(y / block) * 19349663u ^
                               uint64_t(z / block) * 83492791u ^ uint64_t(trial);
          grid[{x, y, z}] = uint8_t((key * 0x9E3779B97F4A7C15ull) >> 61);  // 8 values: many ties
        }
    expectRoundTrip(grid, "random blocks trial " + std::to_string(trial));
  }
}

TEST(OctreeVolume, ConsolidatesUniformRegions) {
  DenseGrid<uint8_t> grid({64, 64, 64});  // all zero but one voxel
  grid[{40, 9, 33}] = 200;
  const OctreeVolume<uint8_t> octree = OctreeVolume<uint8_t>::build(grid);
  EXPECT_EQ(octree.maxDepth(), 6);
  EXPECT_EQ(octree.caps().size(), 1u);  // one cap on the path to the voxel
  EXPECT_EQ(octree.nodeCount(), 5u);    // one node per depth 0 … d_max − 2
  EXPECT_EQ(octree.voxel({40, 9, 33}), 200);
}

TEST(OctreeVolume, LossyStaysWithinItsErrorBound) {
  const DenseGrid<uint8_t> grid = quantise8(makeVolumeField({VolumeField::Smoke, {40, 40, 40}, 3}));
  const OctreeVolume<uint8_t> lossless = OctreeVolume<uint8_t>::build(grid);
  const OctreeVolume<uint8_t> lossy = OctreeVolume<uint8_t>::build(grid, {4.0});
  EXPECT_NO_THROW(lossy.validate());
  EXPECT_LT(lossy.bytes(), lossless.bytes());
  // 8 values of variance ≤ 4 lie within √(8·4) of their mean, +0.5 for rounding it: per
  // consolidation level, at most d_max − 1 levels.
  const DenseGrid<uint8_t> decoded = lossy.decode();
  int worst = 0;
  for (size_t i = 0; i < grid.values.size(); ++i)
    worst = std::max(worst, std::abs(int(grid.values[i]) - int(decoded.values[i])));
  EXPECT_LE(worst, (lossy.maxDepth() - 1) * (std::sqrt(32.0) + 0.5));
  EXPECT_GT(worst, 0);
}

// Brute-force min/max over the (h + 1)³ voxels a block's cells touch, outside = 0.
template <class T>
std::pair<T, T> bruteRange(const DenseGrid<T>& grid, glm::ivec3 o, int h) {
  T lo = T(0), hi = T(0);
  bool first = true;
  for (int z = o.z; z <= o.z + h; ++z)
    for (int y = o.y; y <= o.y + h; ++y)
      for (int x = o.x; x <= o.x + h; ++x) {
        const bool in = x < grid.size.x && y < grid.size.y && z < grid.size.z;
        const T v =
            in ? grid.values[size_t(x) + size_t(grid.size.x) * (y + size_t(grid.size.y) * z)]
               : T(0);
        lo = first ? v : std::min(lo, v), hi = first ? v : std::max(hi, v), first = false;
      }
  return {lo, hi};
}

// Random root-to-leaf descents; at each step the child's pair against brute force over
// `field` (the data, or the decoded lossy field). Returns how many isovalues were checked.
template <class T>
int checkMinMax(const OctreeVolume<T>& octree, const DenseGrid<T>& field, bool exact,
                std::mt19937_64& rng, const std::string& what) {
  int checked = 0;
  for (int walk = 0; walk < 400; ++walk) {
    int depth = 0;
    uint32_t index = 0;
    glm::ivec3 origin(0);
    for (;;) {
      const auto& node = octree.nodes(depth)[index];
      const int c = int(rng() % 8), h = 1 << (octree.maxDepth() - depth - 1);
      const glm::ivec3 o = origin + glm::ivec3((c >> 2) & 1, (c >> 1) & 1, c & 1) * h;
      const auto [lo, hi] = bruteRange(field, o, h);
      if (exact) {  // lossless: the pair is exactly the block's range (27 voxels for a cap)
        EXPECT_EQ(node.childMins[c], lo) << what << " depth " << depth;
        EXPECT_EQ(node.childMaxs[c], hi) << what << " depth " << depth;
      }
      EXPECT_LE(node.childMins[c], lo) << what << " depth " << depth;
      EXPECT_GE(node.childMaxs[c], hi) << what << " depth " << depth;
      // A random isovalue some cell of the block straddles is never rejected.
      if (lo < hi) {
        const double iso = lo + (hi - lo) * std::uniform_real_distribution<double>(0, 1)(rng);
        EXPECT_TRUE(node.childMins[c] <= iso && iso < node.childMaxs[c]) << what;
        ++checked;
      }
      if (node.childOffset[c] < 0 || depth == octree.maxDepth() - 2) break;
      index = node.childStart + uint32_t(node.childOffset[c]);
      origin = o;
      ++depth;
    }
  }
  return checked;
}

TEST(OctreeVolume, MinMaxTreeNeverRejectsABlockHoldingTheIsovalue) {
  std::mt19937_64 rng(5);
  for (VolumeField field : kVolumeFields) {
    const DenseGrid<float> f = makeVolumeField({field, {37, 30, 33}, 9});
    const DenseGrid<uint8_t> grid = quantise8(f);
    const std::string name = volumeFieldName(field);
    EXPECT_GT(checkMinMax(OctreeVolume<uint8_t>::build(grid), grid, true, rng, name), 100);
    const DenseGrid<uint16_t> grid16 = quantise16(f);
    EXPECT_GT(checkMinMax(OctreeVolume<uint16_t>::build(grid16), grid16, true, rng, name), 100);
    // Lossy: the pairs bound the stored (decoded) field, not the input.
    const OctreeVolume<uint8_t> lossy = OctreeVolume<uint8_t>::build(grid, {6.0});
    EXPECT_GT(checkMinMax(lossy, lossy.decode(), false, rng, name + " lossy"), 50);
  }
}

}  // namespace
}  // namespace penumbra
