#include "core/mesh/lattice_split.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

// A polygon's extent along one axis (0: x, 1: y).
struct Span {
  double low = INFINITY, high = -INFINITY;
};
Span spanOf(const Polygon2& polygon, int axis) {
  Span span;
  for (const Vec2& v : polygon) {
    span.low = std::min(span.low, v[axis]);
    span.high = std::max(span.high, v[axis]);
  }
  return span;
}

// Calls f(at) for each lattice line strictly inside the span by more than eps, left to right,
// until f returns false.
template <class F>
void forLinesInside(const Span& span, double spacing, double eps, F&& f) {
  for (long k = long(std::floor(span.low / spacing)) + 1; double(k) * spacing < span.high; ++k) {
    const double at = double(k) * spacing;
    if (at <= span.low + eps || at >= span.high - eps) continue;
    if (!f(at)) return;
  }
}

// Cuts every piece by the lines coordinate = k·spacing (axis 0: x, 1: y).
std::vector<Polygon2> splitAlong(std::vector<Polygon2> pieces, int axis, double spacing, double eps) {
  std::vector<Polygon2> out;
  for (Polygon2& piece : pieces) {
    const Span span = spanOf(piece, axis);
    Polygon2 rest = std::move(piece);
    forLinesInside(span, spacing, eps, [&](double at) {
      // Directed so that the part below `at` is on the left.
      const Vec2 a = axis == 0 ? Vec2{at, 0.0} : Vec2{1.0, at};
      const Vec2 b = axis == 0 ? Vec2{at, 1.0} : Vec2{0.0, at};
      Split2 split = splitByLine(rest, a, b, eps);
      if (split.left.size() >= 3) out.push_back(std::move(split.left));
      if (split.right.size() < 3) {
        rest.clear();
        return false;
      }
      rest = std::move(split.right);
      return true;
    });
    if (rest.size() >= 3) out.push_back(std::move(rest));
  }
  return out;
}

// Whether splitAlong would cut `cell` along `axis` (the same lines, so skipping it changes nothing).
bool crossedAlong(const Polygon2& cell, int axis, double spacing, double eps) {
  bool crossed = false;
  forLinesInside(spanOf(cell, axis), spacing, eps, [&](double) { return !(crossed = true); });
  return crossed;
}

}  // namespace

std::vector<Polygon2> splitByLattice(const Polygon2& cell, double spacing, double eps) {
  // Most DM cells lie between two lattice lines both ways: no copies through two passes.
  if (!(spacing > 0) || (cell.size() >= 3 && !crossedAlong(cell, 0, spacing, eps) && !crossedAlong(cell, 1, spacing, eps)))
    return {cell};
  return splitAlong(splitAlong({cell}, 0, spacing, eps), 1, spacing, eps);
}

}  // namespace penumbra
