#include "interchange/coplanar_overlaps.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

#include "core/geom/convex2d.h"
#include "core/geom/plane_frame.h"

namespace penumbra::interchange {

namespace {

struct Item {
  FaceRef ref;
  const Polygon3* polygon = nullptr;
  Plane plane;
  Vec3 min{INFINITY}, max{-INFINITY};
};

bool boxesApart(const Item& a, const Item& b, double eps) {
  for (int c = 0; c < 3; ++c)
    if (a.min[c] > b.max[c] + eps || b.min[c] > a.max[c] + eps) return true;
  return false;
}

bool allWithin(const Polygon3& polygon, const Plane& plane, double eps) {
  return std::all_of(polygon.begin(), polygon.end(),
                     [&](const Vec3& p) { return std::abs(plane.signedDistance(p)) <= eps; });
}

// The same corners, the other way round (a face and its reverse).
bool reverseOf(const Polygon3& a, const Polygon3& b) {
  if (a.size() != b.size()) return false;
  const Polygon3 reversed(b.rbegin(), b.rend());
  for (size_t start = 0; start < a.size(); ++start) {
    bool all = true;
    for (size_t k = 0; k < a.size() && all; ++k) all = a[(start + k) % a.size()] == reversed[k];
    if (all) return true;
  }
  return false;
}

// Twice the area over the largest corner distance (polygon.h width(), in 2D).
double width2(const Polygon2& polygon) {
  double size = 0;
  for (size_t i = 0; i < polygon.size(); ++i)
    for (size_t j = i + 1; j < polygon.size(); ++j)
      size = std::max(size, glm::length(polygon[i] - polygon[j]));
  return size > 0 ? 2 * std::abs(signedArea(polygon)) / size : 0;
}

bool within(const Polygon2& inner, const Polygon2& outer, double eps) {
  return std::all_of(inner.begin(), inner.end(),
                     [&](const Vec2& p) { return contains(outer, p, eps); });
}

// The overlap of two items already known to be near each other, if any.
std::optional<CoplanarOverlap> overlapOf(const Item& a, const Item& b, const Tolerance& tolerance) {
  const double onPlane = tolerance.onPlane();
  // Clearly tilted planes first (cheap); then the corners, both ways.
  if (std::abs(glm::dot(a.plane.normal, b.plane.normal)) < 0.5) return std::nullopt;
  if (!allWithin(*b.polygon, a.plane, onPlane) || !allWithin(*a.polygon, b.plane, onPlane))
    return std::nullopt;
  const bool backToBack = glm::dot(a.plane.normal, b.plane.normal) < 0;
  if (backToBack && a.ref.group == b.ref.group && reverseOf(*a.polygon, *b.polygon))
    return std::nullopt;

  // In a's plane: a is counter-clockwise there, b is made so.
  const PlaneFrame frame = PlaneFrame::onPlane(a.plane, a.polygon->front());
  Polygon2 a2, b2;
  for (const Vec3& p : *a.polygon) a2.push_back(frame.to2D(p));
  for (const Vec3& p : *b.polygon) b2.push_back(frame.to2D(p));
  b2 = counterClockwise(std::move(b2));
  const Polygon2 common = intersect(a2, b2, tolerance.length());
  if (common.size() < 3 || width2(common) <= tolerance.minFaceWidth()) return std::nullopt;

  CoplanarOverlap overlap{a.ref, b.ref, backToBack, std::abs(signedArea(common)), std::nullopt};
  if (!backToBack) {
    const bool aInB = within(a2, b2, tolerance.minFaceWidth()),
               bInA = within(b2, a2, tolerance.minFaceWidth());
    if (bInA)
      overlap.covered = b.ref;  // also when both: the later of two equal faces goes
    else if (aInB)
      overlap.covered = a.ref;
  }
  return overlap;
}

}  // namespace

std::vector<CoplanarOverlap> findCoplanarOverlaps(const std::vector<std::vector<Polygon3>>& groups,
                                                  const Tolerance& tolerance) {
  std::vector<Item> items;
  Vec3 low{INFINITY}, high{-INFINITY};
  for (size_t g = 0; g < groups.size(); ++g)
    for (size_t f = 0; f < groups[g].size(); ++f) {
      const auto plane = planeOf(groups[g][f]);
      if (!plane) continue;  // no area: overlaps nothing
      Item item{{g, f}, &groups[g][f], *plane};
      for (const Vec3& p : groups[g][f]) {
        item.min = glm::min(item.min, p);
        item.max = glm::max(item.max, p);
      }
      low = glm::min(low, item.min);
      high = glm::max(high, item.max);
      items.push_back(item);
    }
  // Sweep along the scene's longest axis: only faces whose boxes meet are compared.
  const Vec3 span = high - low;
  const int axis = span.x >= span.y && span.x >= span.z ? 0 : span.y >= span.z ? 1 : 2;
  std::vector<size_t> order(items.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::sort(order.begin(), order.end(),
            [&](size_t i, size_t j) { return items[i].min[axis] < items[j].min[axis]; });

  const double eps = tolerance.onPlane();
  std::vector<CoplanarOverlap> found;
  for (size_t k = 0; k < order.size(); ++k) {
    const Item& first = items[order[k]];
    for (size_t m = k + 1; m < order.size() && items[order[m]].min[axis] <= first.max[axis] + eps;
         ++m) {
      const Item& second = items[order[m]];
      if (boxesApart(first, second, eps)) continue;
      const bool inOrder = first.ref < second.ref;
      const auto overlap = overlapOf(inOrder ? first : second, inOrder ? second : first, tolerance);
      if (overlap) found.push_back(*overlap);
    }
  }
  std::sort(found.begin(), found.end(), [](const CoplanarOverlap& x, const CoplanarOverlap& y) {
    return std::tie(x.a, x.b) < std::tie(y.a, y.b);
  });
  return found;
}

CoplanarDecision decideCoplanarOverlaps(const std::vector<CoplanarOverlap>& overlaps) {
  CoplanarDecision decision;
  for (const CoplanarOverlap& o : overlaps)
    if (o.covered) decision.dropped.emplace(*o.covered, *o.covered == o.a ? o.b : o.a);
  // Name a coverer that stays where one does (a face within a dropped one lies within what covers
  // that).
  for (const CoplanarOverlap& o : overlaps) {
    if (!o.covered) continue;
    const FaceRef by = *o.covered == o.a ? o.b : o.a;
    if (!decision.dropped.count(by)) decision.dropped[*o.covered] = by;
  }
  for (const CoplanarOverlap& o : overlaps)
    if (!decision.dropped.count(o.a) && !decision.dropped.count(o.b)) decision.kept.push_back(o);
  return decision;
}

}  // namespace penumbra::interchange
