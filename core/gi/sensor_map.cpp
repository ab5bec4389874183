#include "core/gi/sensor_map.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra::gi {

namespace {
constexpr int kSub = 4;  // sub-texels per side for a texel's centroid
}  // namespace

Vec2 concentricDisc(const Vec2& square) {
  const double a = square.x, b = square.y;
  if (a == 0 && b == 0) return Vec2(0.0);
  double r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = M_PI / 4 * (b / a);
  } else {
    r = b;
    phi = M_PI / 2 - M_PI / 4 * (a / b);
  }
  return Vec2(r * std::cos(phi), r * std::sin(phi));
}

SensorMap::SensorMap(int size) : size_(size) {
  if (size < 1 || size > kMaxSize)
    throw std::invalid_argument("sensor map size " + std::to_string(size) + " is outside 1.." +
                                std::to_string(kMaxSize));
  weight_ = 1.0 / (double(size) * double(size));
  directions_.reserve(size_t(size) * size_t(size));
  for (int i = 0; i < size; ++i) {
    for (int j = 0; j < size; ++j) {
      // The centroid of the texel's disc image (from kSub² sub-texel centres; the map keeps
      // areas, so a plain mean), lifted: the direction the texel's weight stands for.
      Vec2 centroid(0.0);
      for (int a = 0; a < kSub; ++a)
        for (int b = 0; b < kSub; ++b)
          centroid += concentricDisc(Vec2(-1 + (2 * (j * kSub + b) + 1) / double(size * kSub),
                                          -1 + (2 * (i * kSub + a) + 1) / double(size * kSub)));
      centroid /= double(kSub * kSub);
      const double z = std::sqrt(std::max(0.0, 1 - glm::dot(centroid, centroid)));
      directions_.push_back(glm::normalize(Vec3(centroid.x, centroid.y, z)));
    }
  }
}

}  // namespace penumbra::gi
