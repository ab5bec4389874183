#include "core/gi/sensor_map.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra::gi {

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
      const Vec2 square(-1 + (2 * j + 1) / double(size), -1 + (2 * i + 1) / double(size));
      const Vec2 d = concentricDisc(square);
      const double z = std::sqrt(std::max(0.0, 1 - d.x * d.x - d.y * d.y));
      directions_.push_back(glm::normalize(Vec3(d.x, d.y, z)));
    }
  }
}

}  // namespace penumbra::gi
