// Seeded random convex polygons for the visible-part tests (VisibleRegion,
// VisibleContour). Free function; thread-safe with one generator per caller.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/geom/convex2d.h"

namespace penumbra::testing {

// A random convex CCW polygon: sorted angles on an ellipse, turned and moved.
inline Polygon2 randomConvex(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> unit(0, 1);
  const int count = 3 + int(unit(rng) * 6);
  std::vector<double> angles(count);
  for (double& a : angles) a = unit(rng) * 2 * M_PI;
  std::sort(angles.begin(), angles.end());
  const Vec2 center{unit(rng) * 2 - 1, unit(rng) * 2 - 1};
  const double sx = scale * (0.1 + unit(rng)), sy = scale * (0.1 + unit(rng)), rot = unit(rng) * 2 * M_PI;
  Polygon2 out;
  for (double a : angles) {
    const Vec2 q{sx * std::cos(a), sy * std::sin(a)};
    out.push_back(center + Vec2{std::cos(rot) * q.x - std::sin(rot) * q.y, std::sin(rot) * q.x + std::cos(rot) * q.y});
  }
  return out;
}

}  // namespace penumbra::testing
