#include "core/shadow/plane_trace.h"

#include <cmath>

namespace penumbra {

PlaneTrace PlaneTrace::of(const Plane& plane, const PlaneFrame& frame, const Tolerance& tol) {
  // plane(to3D(u)) = plane(origin) + u.x (n·U) + u.y (n·V): affine in u.
  const double c0 = plane.signedDistance(frame.origin);
  const Vec2 g{glm::dot(plane.normal, frame.u), glm::dot(plane.normal, frame.v)};
  const double tilt = glm::length(g);
  const double eps = tol.length();
  PlaneTrace trace;
  if (tilt * tol.sceneSize <= eps) {
    trace.kind = std::abs(c0) <= eps ? Kind::Coincident : (c0 > 0 ? Kind::Front : Kind::Back);
    return trace;
  }
  // Normalise so values are true 2D distances (the 3D distance grows by 1/tilt).
  trace.kind = Kind::Line;
  trace.normal = g / tilt;
  trace.offset = c0 / tilt;
  return trace;
}

Polygon2 clipFrontOf(const Polygon2& polygon, const PlaneTrace& trace, double eps) {
  switch (trace.kind) {
    case PlaneTrace::Kind::Front:
    case PlaneTrace::Kind::Coincident:
      return polygon;
    case PlaneTrace::Kind::Back:
      return {};
    case PlaneTrace::Kind::Line:
      break;
  }
  const size_t count = polygon.size();
  if (count < 3) return {};
  std::vector<double> value(count);
  std::vector<int> side(count);
  bool anyFront = false, anyBack = false;
  for (size_t i = 0; i < count; ++i) {
    value[i] = trace.value(polygon[i]);
    side[i] = value[i] > eps ? 1 : (value[i] < -eps ? -1 : 0);
    anyFront |= side[i] > 0;
    anyBack |= side[i] < 0;
  }
  if (!anyBack) return polygon;
  if (!anyFront) return {};
  Polygon2 out;
  out.reserve(count + 1);
  for (size_t i = 0; i < count; ++i) {
    const size_t j = (i + 1) % count;
    if (side[i] >= 0) out.push_back(polygon[i]);
    if (side[i] * side[j] < 0) {
      const double t = value[i] / (value[i] - value[j]);
      out.push_back(polygon[i] + t * (polygon[j] - polygon[i]));
    }
  }
  return out;
}

std::optional<Chord> chordAlong(const Polygon2& polygon, const PlaneTrace& trace, double eps,
                                double minLength) {
  if (trace.kind != PlaneTrace::Kind::Line || polygon.size() < 3) return std::nullopt;
  // Points of the polygon's boundary on the line: vertices within eps, strict crossings.
  const Vec2 along{-trace.normal.y, trace.normal.x};
  bool any = false;
  double lo = 0, hi = 0;
  Vec2 loPoint{0.0}, hiPoint{0.0};
  auto add = [&](const Vec2& p) {
    const double t = glm::dot(p, along);
    if (!any || t < lo) lo = t, loPoint = p;
    if (!any || t > hi) hi = t, hiPoint = p;
    any = true;
  };
  const size_t count = polygon.size();
  for (size_t i = 0; i < count; ++i) {
    const Vec2& p = polygon[i];
    const Vec2& q = polygon[(i + 1) % count];
    const double vp = trace.value(p), vq = trace.value(q);
    if (std::abs(vp) <= eps) add(p);
    if ((vp > eps && vq < -eps) || (vp < -eps && vq > eps)) add(p + vp / (vp - vq) * (q - p));
  }
  if (!any || !(hi - lo > minLength)) return std::nullopt;
  return Chord{loPoint, hiPoint};
}

}  // namespace penumbra
