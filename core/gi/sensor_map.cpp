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

namespace {

// The lifted centroid of the disc image of the rectangle [x0, x0 + w] × [y0, y0 + h] (in
// [-1, 1]²), from kSub² sub-rectangle centres (the map keeps areas, so a plain mean).
Vec3 liftedCentroid(double x0, double y0, double w, double h) {
  Vec2 centroid(0.0);
  for (int a = 0; a < kSub; ++a)
    for (int b = 0; b < kSub; ++b)
      centroid += concentricDisc(Vec2(x0 + (b + 0.5) * w / kSub, y0 + (a + 0.5) * h / kSub));
  centroid /= double(kSub * kSub);
  const double z = std::sqrt(std::max(0.0, 1 - glm::dot(centroid, centroid)));
  return glm::normalize(Vec3(centroid.x, centroid.y, z));
}

}  // namespace

SensorMap::SensorMap(int size, int rimRings, int rimSplit) : size_(size) {
  if (size < 1 || size > kMaxSize)
    throw std::invalid_argument("sensor map size " + std::to_string(size) + " is outside 1.." +
                                std::to_string(kMaxSize));
  if (rimRings < 0 || rimSplit < 1 || rimSplit > 16) throw std::invalid_argument("sensor map rim split");
  weight_ = 1.0 / (double(size) * double(size));
  directions_.reserve(size_t(size) * size_t(size));
  const double w = 2.0 / size;  // a texel's side in [-1, 1]²
  for (int i = 0; i < size; ++i) {
    for (int j = 0; j < size; ++j) {
      const double x0 = -1 + j * w, y0 = -1 + i * w;
      directions_.push_back(liftedCentroid(x0, y0, w, w));
      // A rim texel is split across the ring only (radially: along x on the square's left and
      // right sides, along y on its top and bottom, both at corners): elevation is what
      // varies fast there; azimuth is already resolved.
      const int ring = std::min({i, j, size - 1 - i, size - 1 - j});  // 0: the outermost
      const bool rim = ring < rimRings && rimSplit > 1;
      const int alongX = rim && (j == ring || j == size - 1 - ring) ? rimSplit : 1;
      const int alongY = rim && (i == ring || i == size - 1 - ring) ? rimSplit : 1;
      if (alongX * alongY == 1) {
        rays_.push_back({directions_.back(), weight_});
        continue;
      }
      for (int a = 0; a < alongY; ++a)
        for (int b = 0; b < alongX; ++b)
          rays_.push_back({liftedCentroid(x0 + b * w / alongX, y0 + a * w / alongY, w / alongX, w / alongY),
                           weight_ / double(alongX * alongY)});
    }
  }
}

}  // namespace penumbra::gi
