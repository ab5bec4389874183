#include "core/geom/clip.h"

#include <algorithm>

namespace penumbra {

namespace {

// Shared by clipFront and split: one classification, one set of cut points.
template <bool kWantFront, bool kWantBack>
void clipSides(const Polygon3& polygon, const Plane& plane, double eps, Polygon3* front,
               Polygon3* back) {
  const size_t count = polygon.size();
  if (count < 3) return;
  // Classify once: +1 front, -1 back, 0 on (within eps).
  thread_local std::vector<double> distance;
  thread_local std::vector<int> side;
  distance.resize(count);
  side.resize(count);
  bool anyFront = false, anyBack = false;
  for (size_t i = 0; i < count; ++i) {
    distance[i] = plane.signedDistance(polygon[i]);
    side[i] = distance[i] > eps ? 1 : (distance[i] < -eps ? -1 : 0);
    anyFront |= side[i] > 0;
    anyBack |= side[i] < 0;
  }
  if (!anyBack) {
    if (kWantFront && anyFront) *front = polygon;
    return;
  }
  if (!anyFront) {
    if (kWantBack) *back = polygon;
    return;
  }
  for (size_t i = 0; i < count; ++i) {
    const size_t j = (i + 1) % count;
    if (side[i] >= 0 && kWantFront) front->push_back(polygon[i]);
    if (side[i] <= 0 && kWantBack) back->push_back(polygon[i]);
    if (side[i] * side[j] < 0) {
      // A strict crossing, interpolated along the edge's own direction: both
      // sides, and the flipped plane, get bit-identical cut points.
      const double t = distance[i] / (distance[i] - distance[j]);
      const Vec3 cut = polygon[i] + t * (polygon[j] - polygon[i]);
      if (kWantFront) front->push_back(cut);
      if (kWantBack) back->push_back(cut);
    }
  }
}

}  // namespace

Polygon3 clipFront(const Polygon3& polygon, const Plane& plane, double eps) {
  Polygon3 front;
  clipSides<true, false>(polygon, plane, eps, &front, nullptr);
  return front;
}

Split3 splitByPlane(const Polygon3& polygon, const Plane& plane, double eps) {
  Split3 out;
  clipSides<true, true>(polygon, plane, eps, &out.front, &out.back);
  return out;
}

}  // namespace penumbra
