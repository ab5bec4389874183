// Splitting a convex polygon (2D or 3D vertices) by a signed distance function:
// one classification, one set of cut points for both sides. Header-only template
// used by clip.cpp (planes) and convex2d.cpp (lines); thread-safe.
#pragma once

#include <type_traits>
#include <vector>

namespace penumbra {

// `distanceOf(v)` is the signed distance of vertex v (positive = front/left).
// Vertices within eps count as on the boundary and go to both sides. A side is
// filled only if some vertex lies strictly (beyond eps) on it; null sides are skipped.
template <typename Vertex, typename DistanceOf>
void splitConvex(const std::vector<Vertex>& polygon, DistanceOf distanceOf, double eps,
                 std::type_identity_t<std::vector<Vertex>>* front,
                 std::type_identity_t<std::vector<Vertex>>* back) {
  const size_t count = polygon.size();
  if (count < 3) return;
  thread_local std::vector<double> distance;
  thread_local std::vector<int> side;
  distance.resize(count);
  side.resize(count);
  bool anyFront = false, anyBack = false;
  for (size_t i = 0; i < count; ++i) {
    distance[i] = distanceOf(polygon[i]);
    side[i] = distance[i] > eps ? 1 : (distance[i] < -eps ? -1 : 0);
    anyFront |= side[i] > 0;
    anyBack |= side[i] < 0;
  }
  if (!anyBack) {
    if (front && anyFront) *front = polygon;
    return;
  }
  if (!anyFront) {
    if (back) *back = polygon;
    return;
  }
  for (size_t i = 0; i < count; ++i) {
    const size_t j = (i + 1) % count;
    if (side[i] >= 0 && front) front->push_back(polygon[i]);
    if (side[i] <= 0 && back) back->push_back(polygon[i]);
    if (side[i] * side[j] < 0) {
      // A strict crossing, interpolated along the edge's own direction: both
      // sides (and the flipped plane or line) get bit-identical cut points.
      const double t = distance[i] / (distance[i] - distance[j]);
      const Vertex cut = polygon[i] + t * (polygon[j] - polygon[i]);
      if (front) front->push_back(cut);
      if (back) back->push_back(cut);
    }
  }
}

}  // namespace penumbra
