#include "core/volume/macrocell_grid.h"

#include <algorithm>
#include <stdexcept>

#include "core/volume/cell_hit.h"
#include "core/volume/cell_walk.h"

namespace penumbra::volume {

template <class T>
MacrocellGrid<T>::MacrocellGrid(const DenseGrid<T>& grid, int cellsPerMacrocell)
    : grid_(grid), side_(cellsPerMacrocell) {
  if (side_ < 1) throw std::invalid_argument("macrocell side < 1");
  const glm::ivec3 cells = grid.size - 1;  // cells of the traced box
  count_ = (cells + side_ - 1) / side_;
  ranges_.assign(size_t(count_.x) * count_.y * count_.z, {T(0), T(0)});
  for (int mz = 0; mz < count_.z; ++mz)
    for (int my = 0; my < count_.y; ++my)
      for (int mx = 0; mx < count_.x; ++mx) {
        const glm::ivec3 lo = glm::ivec3(mx, my, mz) * side_;
        const glm::ivec3 hi = glm::min(lo + side_, cells);  // corners of the last cells
        std::array<T, 2> range{grid.at(lo), grid.at(lo)};
        for (int z = lo.z; z <= hi.z; ++z)
          for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x) {
              const T v = grid.values[grid.index({x, y, z})];
              range = {std::min(range[0], v), std::max(range[1], v)};
            }
        ranges_[size_t(mx) + size_t(count_.x) * (size_t(my) + size_t(count_.y) * mz)] = range;
      }
}

template <class T>
std::optional<VolumeHit> MacrocellGrid<T>::trace(const VolumeRay& ray, double iso,
                                                 TraceCounters* counters) const {
  const glm::ivec3 cells = grid_.size - 1;
  const auto span = clipToBox(ray, Vec3(0.0), Vec3(cells));
  if (!span) return std::nullopt;
  const Vec3 o = ray.origin, d = ray.dir;
  std::optional<VolumeHit> hit;
  auto visitCell = [&](glm::ivec3 v, double ta, double tb) {
    CellCorners corners;
    for (int c = 0; c < 8; ++c)
      corners[c] =
          double(grid_.values[grid_.index(v + glm::ivec3((c >> 2) & 1, (c >> 1) & 1, c & 1))]);
    if (counters) ++counters->cells;
    const auto [lo, hi] = std::minmax_element(corners.begin(), corners.end());
    if (!(*lo <= iso && iso < *hi) || !(ta <= tb)) return false;
    if (counters) ++counters->cubics;
    const Vec3 entry = o + d * ta - Vec3(v);  // cubic from the segment's entry (as the octree)
    const std::optional<double> s = firstRoot(cellCubic(corners, entry, d, iso), 0.0, tb - ta);
    if (!s) return false;
    const Vec3 g = trilinearGradient(corners, entry + d * *s);
    const double length = glm::length(g);
    hit = VolumeHit{ta + *s, length > 0.0 ? g / length : -glm::normalize(d)};
    return true;
  };
  walkCells(o, d, span->t0, span->t1, double(side_), glm::ivec3(0), count_ - 1,
            [&](glm::ivec3 m, double ta, double tb) {
              if (counters) ++counters->nodes;
              const auto& range =
                  ranges_[size_t(m.x) + size_t(count_.x) * (size_t(m.y) + size_t(count_.y) * m.z)];
              if (!(double(range[0]) <= iso && iso < double(range[1]))) return false;
              const glm::ivec3 lo = m * side_, hi = glm::min(lo + side_, cells) - 1;
              return walkCells(o, d, ta, tb, 1.0, lo, hi, visitCell);
            });
  return hit;
}

template class MacrocellGrid<uint8_t>;
template class MacrocellGrid<uint16_t>;
template class MacrocellGrid<float>;

}  // namespace penumbra::volume
