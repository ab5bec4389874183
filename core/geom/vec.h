// Vector types used everywhere in core: GLM in double precision.
// Plain values; thread-safe to copy and read.
#pragma once

#include <glm/glm.hpp>

namespace penumbra {

using Vec2 = glm::dvec2;
using Vec3 = glm::dvec3;
using Mat3 = glm::dmat3;
using Mat4 = glm::dmat4;

inline double cross2(const Vec2& a, const Vec2& b) { return a.x * b.y - a.y * b.x; }

}  // namespace penumbra
