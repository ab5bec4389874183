// An orthonormal 2D frame on a plane: origin, u, v with u × v = the plane's normal
// (CCW seen from the front stays CCW in 2D). Plain value, set once; thread-safe.
#pragma once

#include <cmath>

#include "core/geom/plane.h"
#include "core/geom/vec.h"

namespace penumbra {

struct PlaneFrame {
  Vec3 origin{0.0};
  Vec3 u{1, 0, 0};
  Vec3 v{0, 1, 0};
  Vec3 normal{0, 0, 1};

  // The same frame, bit for bit (a display memo is only valid for the frame it was made in).
  bool operator==(const PlaneFrame&) const = default;

  // A frame on `plane` whose origin is `point` projected onto the plane.
  static PlaneFrame onPlane(const Plane& plane, const Vec3& point) {
    const Vec3 n = plane.normal;
    // Cross with the axis least aligned with n: never near-parallel.
    const Vec3 a = std::abs(n.x) <= std::abs(n.y) && std::abs(n.x) <= std::abs(n.z) ? Vec3{1, 0, 0}
                   : std::abs(n.y) <= std::abs(n.z)                               ? Vec3{0, 1, 0}
                                                                                   : Vec3{0, 0, 1};
    const Vec3 u = glm::normalize(glm::cross(a, n));
    return PlaneFrame{plane.project(point), u, glm::cross(n, u), n};
  }

  // Drops the out-of-plane component.
  Vec2 to2D(const Vec3& p) const {
    const Vec3 d = p - origin;
    return Vec2{glm::dot(d, u), glm::dot(d, v)};
  }
  Vec3 to3D(const Vec2& q) const { return origin + q.x * u + q.y * v; }
};

}  // namespace penumbra
