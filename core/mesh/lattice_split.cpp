#include "core/mesh/lattice_split.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

// Cuts every piece by the lines coordinate = k·spacing (axis 0: x, 1: y).
std::vector<Polygon2> splitAlong(std::vector<Polygon2> pieces, int axis, double spacing, double eps) {
  std::vector<Polygon2> out;
  for (Polygon2& piece : pieces) {
    double low = INFINITY, high = -INFINITY;
    for (const Vec2& v : piece) {
      low = std::min(low, v[axis]);
      high = std::max(high, v[axis]);
    }
    Polygon2 rest = std::move(piece);
    // Lines strictly inside the piece's span, left to right.
    for (long k = long(std::floor(low / spacing)) + 1; double(k) * spacing < high; ++k) {
      const double at = double(k) * spacing;
      if (at <= low + eps || at >= high - eps) continue;
      // Directed so that the part below `at` is on the left.
      const Vec2 a = axis == 0 ? Vec2{at, 0.0} : Vec2{1.0, at};
      const Vec2 b = axis == 0 ? Vec2{at, 1.0} : Vec2{0.0, at};
      Split2 split = splitByLine(rest, a, b, eps);
      if (split.left.size() >= 3) out.push_back(std::move(split.left));
      if (split.right.size() < 3) {
        rest.clear();
        break;
      }
      rest = std::move(split.right);
    }
    if (rest.size() >= 3) out.push_back(std::move(rest));
  }
  return out;
}

// Whether splitAlong would cut `cell` along `axis`: some line strictly inside its span by
// more than eps (the same test, so skipping it changes nothing).
bool crossedAlong(const Polygon2& cell, int axis, double spacing, double eps) {
  double low = INFINITY, high = -INFINITY;
  for (const Vec2& v : cell) {
    low = std::min(low, v[axis]);
    high = std::max(high, v[axis]);
  }
  for (long k = long(std::floor(low / spacing)) + 1; double(k) * spacing < high; ++k) {
    const double at = double(k) * spacing;
    if (at > low + eps && at < high - eps) return true;
  }
  return false;
}

}  // namespace

std::vector<Polygon2> splitByLattice(const Polygon2& cell, double spacing, double eps) {
  // Most DM cells lie between two lattice lines both ways: no copies through two passes.
  if (!(spacing > 0) || (cell.size() >= 3 && !crossedAlong(cell, 0, spacing, eps) && !crossedAlong(cell, 1, spacing, eps)))
    return {cell};
  return splitAlong(splitAlong({cell}, 0, spacing, eps), 1, spacing, eps);
}

}  // namespace penumbra
