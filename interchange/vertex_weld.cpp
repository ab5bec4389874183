#include "interchange/vertex_weld.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace penumbra::interchange {

namespace {

struct CellKey {
  int64_t x, y, z;
  bool operator==(const CellKey&) const = default;
};

struct CellHash {
  size_t operator()(const CellKey& k) const {
    return (uint64_t(k.x) * 73856093u) ^ (uint64_t(k.y) * 19349663u) ^ (uint64_t(k.z) * 83492791u);  // wraps
  }
};

}  // namespace

WeldResult weldVertices(const std::vector<Vec3>& positions, double eps) {
  WeldResult result;
  result.remap.resize(positions.size());
  // Grid of cell size eps: a match lies in the same or a neighbouring cell.
  std::unordered_multimap<CellKey, int, CellHash> grid;
  // Cell indices are clamped into int64 range: a vertex ~1e18 cells away (an unused vertex far
  // from a tiny model) shares an edge cell with others, and the distance check below still
  // decides (a fuzz finding: the conversion overflowed).
  auto cellIndex = [eps](double x) {
    return int64_t(std::clamp(std::floor(x / eps), -1e18, 1e18));
  };
  auto cellOf = [&](const Vec3& p) { return CellKey{cellIndex(p.x), cellIndex(p.y), cellIndex(p.z)}; };
  for (size_t i = 0; i < positions.size(); ++i) {
    const Vec3& p = positions[i];
    const CellKey cell = cellOf(p);
    int found = -1;
    for (int dx = -1; dx <= 1 && found < 0; ++dx)
      for (int dy = -1; dy <= 1 && found < 0; ++dy)
        for (int dz = -1; dz <= 1 && found < 0; ++dz) {
          const auto range = grid.equal_range({cell.x + dx, cell.y + dy, cell.z + dz});
          for (auto it = range.first; it != range.second; ++it) {
            const Vec3 d = glm::abs(result.positions[size_t(it->second)] - p);
            if (d.x <= eps && d.y <= eps && d.z <= eps) {
              found = it->second;
              break;
            }
          }
        }
    if (found >= 0) {
      result.remap[i] = found;
      ++result.merged;
    } else {
      result.remap[i] = int(result.positions.size());
      grid.emplace(cell, int(result.positions.size()));
      result.positions.push_back(p);
    }
  }
  return result;
}

}  // namespace penumbra::interchange
