#include "core/scene/transform.h"

#include <cmath>

namespace penumbra {

namespace {
// Column-major GLM matrices: m[column][row].
Mat3 rotationX(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return Mat3(1, 0, 0, 0, c, s, 0, -s, c);
}
Mat3 rotationY(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return Mat3(c, 0, -s, 0, 1, 0, s, 0, c);
}
Mat3 rotationZ(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return Mat3(c, s, 0, -s, c, 0, 0, 0, 1);
}
}  // namespace

Mat3 Transform::rotation() const {
  const Vec3 r = glm::radians(rotateDeg);
  return rotationX(r.x) * rotationY(r.y) * rotationZ(r.z);
}

Mat4 Transform::worldFromObject() const {
  const Mat3 rs = rotation() * Mat3(scale.x, 0, 0, 0, scale.y, 0, 0, 0, scale.z);
  Mat4 m(rs);
  m[3] = glm::dvec4(translate, 1.0);
  return m;
}

Vec3 Transform::apply(const Vec3& p) const { return translate + rotation() * (scale * p); }

}  // namespace penumbra
