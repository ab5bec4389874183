#include "core/overlap/penumbra_volume.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/geom/clip.h"

namespace penumbra {

namespace {

// How far from 1 a stored normal's length may be (rounding of one normalisation).
constexpr double kUnitNormalSlack = 1e-12;

struct Extent {
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
};

Extent extentAlong(const Vec3& normal, const Polygon3& polygon) {
  Extent e;
  for (const Vec3& p : polygon) {
    const double d = glm::dot(normal, p);
    e.min = std::min(e.min, d);
    e.max = std::max(e.max, d);
  }
  return e;
}

// Adds the plane through edge a→b and vertex v if, with its computed normal, it
// separates the light (one closed side) from the face (the other). The kept
// half-space is the face's side, bounded at the face's outermost vertex.
void addSeparatingPlane(const Vec3& a, const Vec3& b, const Vec3& v, const Polygon3& light,
                        const Polygon3& face, const Tolerance& tolerance,
                        std::vector<Plane>& out) {
  const Vec3 edge = b - a;
  const Vec3 n = glm::cross(edge, v - a);
  const double length = glm::length(n);
  // v within length() of the edge's line: no well-defined plane; dropping it
  // only enlarges the volume.
  if (!(length > tolerance.length() * glm::length(edge))) return;
  const Vec3 normal = n / length;
  const Extent l = extentAlong(normal, light);
  const Extent f = extentAlong(normal, face);
  // Supporting planes touch both polygons (often along parallel edges), so the
  // separation test sees rounding noise at zero: allow an overlap of length().
  // A light vertex that overlaps by δ could let points beyond the plane be
  // reached, but only by δ·|x − p|/|p − s| (x the point, p on the face, s on the
  // light): within the onPlane() widening unless the face lies within 1/1000 of
  // the cube's size from the light.
  const double slack = tolerance.length();
  if (f.max <= l.min + slack) {
    out.push_back(Plane{normal, -f.max});  // keeps normal·x ≤ f.max
  } else if (l.max <= f.min + slack) {
    out.push_back(Plane{-normal, f.min});  // keeps normal·x ≥ f.min
  }
}

}  // namespace

bool PenumbraVolume::contains(const Vec3& x) const {
  return std::all_of(bounds.begin(), bounds.end(),
                     [&](const Plane& plane) { return plane.signedDistance(x) <= 0; });
}

void PenumbraVolume::validate() const {
  if (bounds.empty()) throw std::logic_error("PenumbraVolume: no bounding plane");
  for (const Plane& plane : bounds) {
    const double n = glm::length(plane.normal);
    if (!std::isfinite(plane.offset) || !std::isfinite(n) || std::abs(n - 1) > kUnitNormalSlack)
      throw std::logic_error("PenumbraVolume: bounding plane is not finite and unit");
  }
}

std::optional<PenumbraVolume> penumbraVolume(const Polygon3& face, const Plane& facePlane,
                                             const Polygon3& light, const Tolerance& tolerance,
                                             VolumeMargin margin) {
  // The part of the light in front of the face. clipFront keeps vertices within
  // length() of the plane unmoved, so this is a superset of the strictly-front
  // part: a larger light gives a larger (safe) volume.
  const Polygon3 front = clipFront(light, facePlane, tolerance.length());
  if (front.size() < 3 || face.size() < 3) return std::nullopt;

  PenumbraVolume volume;
  volume.bounds.push_back(facePlane);  // behind the face, away from the light
  for (size_t i = 0; i < front.size(); ++i) {
    const Vec3& a = front[i];
    const Vec3& b = front[(i + 1) % front.size()];
    for (const Vec3& v : face) addSeparatingPlane(a, b, v, front, face, tolerance, volume.bounds);
  }
  for (size_t i = 0; i < face.size(); ++i) {
    const Vec3& a = face[i];
    const Vec3& b = face[(i + 1) % face.size()];
    for (const Vec3& v : front) addSeparatingPlane(a, b, v, front, face, tolerance, volume.bounds);
  }
  // Widen every half-space: rounding here and in later clipping can then only
  // lose points that lie within onPlane() of the exact volume's outside.
  if (margin == VolumeMargin::Conservative)
    for (Plane& plane : volume.bounds) plane.offset -= tolerance.onPlane();
  return volume;
}

bool PenumbraVolume::outsideABound(const Polygon3& polygon) const {
  for (const Plane& bound : bounds)
    if (std::all_of(polygon.begin(), polygon.end(), [&](const Vec3& p) { return bound.signedDistance(p) > 0; }))
      return true;
  return false;
}

Polygon3 PenumbraVolume::clipInside(const Polygon3& polygon, double eps) const {
  Polygon3 inside = polygon;
  for (const Plane& bound : bounds) {
    if (inside.empty()) break;
    inside = clipFront(inside, bound.flipped(), eps);
  }
  return inside;
}

}  // namespace penumbra
