// Front-to-back order of the 8 child octants a ray crosses (Gargantini–Atkinson, as in the
// paper's Appendix C): sort the ray's crossings of the three mid-planes inside (t0, t1) and
// flip one octant bit per crossing. Header-only; pure; thread-safe.
#pragma once

#include <algorithm>
#include <limits>

#include "core/geom/vec.h"

namespace penumbra::volume {

// Calls visit(child, ta, tb) for each octant (index x << 2 | y << 1 | z) of the cube split at
// `center`, in ray order, with the ray's span inside it; stops and returns true as soon as
// visit does.
template <class Visit>
bool walkOctants(const Vec3& origin, const Vec3& dir, const Vec3& invDir, const Vec3& center,
                 double t0, double t1, Visit&& visit) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double crossing[3];
  int child = 0;
  for (int a = 0; a < 3; ++a) {
    crossing[a] = dir[a] != 0.0 ? (center[a] - origin[a]) * invDir[a] : kInf;
    // Side of the mid-plane at t0 from where the crossing lies, not from a rounded position.
    const bool upper = dir[a] == 0.0       ? origin[a] >= center[a]
                       : crossing[a] <= t0 ? dir[a] > 0.0
                                           : dir[a] < 0.0;
    child |= int(upper) << (2 - a);
  }
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int a, int b) { return crossing[a] < crossing[b]; });
  double ta = t0;
  for (int i = 0; i < 3; ++i) {
    const int axis = order[i];
    if (!(crossing[axis] > t0)) continue;
    if (!(crossing[axis] < t1)) break;
    if (visit(child, ta, crossing[axis])) return true;
    ta = crossing[axis];
    child ^= 1 << (2 - axis);
  }
  return visit(child, ta, t1);
}

}  // namespace penumbra::volume
