// Cells of a uniform grid a ray crosses, in order (Amanatides–Woo 3D DDA): the macrocell
// baseline's two levels. Header-only; pure; thread-safe.
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <limits>

#include "core/geom/vec.h"

namespace penumbra::volume {

// Calls visit(cell, ta, tb) for the cells of side `cellSize` with index in [lo, hi] the ray
// crosses within [t0, t1], front to back; stops and returns true as soon as visit does.
template <class Visit>
bool walkCells(const Vec3& origin, const Vec3& dir, double t0, double t1, double cellSize,
               glm::ivec3 lo, glm::ivec3 hi, Visit&& visit) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const Vec3 start = origin + dir * t0;
  glm::ivec3 cell, step;
  double next[3], delta[3];
  for (int a = 0; a < 3; ++a) {
    cell[a] = std::clamp(int(std::floor(start[a] / cellSize)), lo[a], hi[a]);
    step[a] = dir[a] > 0.0 ? 1 : -1;
    if (dir[a] == 0.0) {
      next[a] = delta[a] = kInf;
    } else {
      next[a] = ((cell[a] + (dir[a] > 0.0 ? 1 : 0)) * cellSize - origin[a]) / dir[a];
      delta[a] = cellSize / std::abs(dir[a]);
    }
  }
  double ta = t0;
  for (;;) {
    const int axis = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
    const double tb = std::min(next[axis], t1);
    if (visit(cell, ta, tb)) return true;
    if (tb >= t1) return false;
    cell[axis] += step[axis];
    if (cell[axis] < lo[axis] || cell[axis] > hi[axis]) return false;
    ta = tb;
    next[axis] += delta[axis];
  }
}

}  // namespace penumbra::volume
