// An object's placement: v' = T + R·(S·v), R = Rx·Ry·Rz (three.js 'XYZ' Euler order).
// Plain value; thread-safe.
#pragma once

#include "core/geom/vec.h"

namespace penumbra {

struct Transform {
  Vec3 translate{0.0};
  Vec3 rotateDeg{0.0};
  Vec3 scale{1.0};

  Mat3 rotation() const;
  Mat4 worldFromObject() const;
  Vec3 apply(const Vec3& objectPoint) const;
  // A negative scale product mirrors the object: faces keep their front by
  // reversing their winding in world space.
  bool mirrors() const { return scale.x * scale.y * scale.z < 0; }
  bool operator==(const Transform&) const = default;
};

}  // namespace penumbra
