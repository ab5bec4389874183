// The sensor map covers the hemisphere with texels of equal projected solid angle (F_ij).
#include <gtest/gtest.h>

#include <cmath>

#include "core/gi/sensor_map.h"

namespace penumbra::gi {
namespace {

// Area of the disc image of the square [x0, x1] × [y0, y1] under the concentric map: the
// polygon through its boundary, each side cut into `steps` pieces (chords of the arcs).
double discArea(double x0, double y0, double x1, double y1, int steps) {
  std::vector<Vec2> boundary;
  const Vec2 corners[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  for (int side = 0; side < 4; ++side)
    for (int k = 0; k < steps; ++k)
      boundary.push_back(concentricDisc(glm::mix(corners[side], corners[(side + 1) % 4], double(k) / steps)));
  double twice = 0;
  for (size_t k = 0; k < boundary.size(); ++k) {
    const Vec2& a = boundary[k];
    const Vec2& b = boundary[(k + 1) % boundary.size()];
    twice += a.x * b.y - a.y * b.x;
  }
  return std::abs(twice) / 2;
}

TEST(SensorMap, EveryTexelHasTheProjectedSolidAngleOfItsWeight) {
  for (int size : {1, 4, 16, 33}) {
    const SensorMap map(size);
    double total = 0;
    for (int i = 0; i < size; ++i)
      for (int j = 0; j < size; ++j) {
        const double h = 2.0 / size;
        const double area = discArea(-1 + j * h, -1 + i * h, -1 + (j + 1) * h, -1 + (i + 1) * h, 64);
        // The disc area of a texel is its projected solid angle; F_ij is its share of π.
        EXPECT_NEAR(area / M_PI, map.weight(), 2e-3 * map.weight()) << size << " " << i << " " << j;
        total += area / M_PI;
      }
    EXPECT_NEAR(total, 1.0, 1e-3) << size;
    EXPECT_NEAR(map.weight() * double(map.texels()), 1.0, 1e-12);
  }
}

// Σ F_ij cosθ_ij − 2/3: the texels' quadrature of E[cosθ] under projected-solid-angle weights
// (exact: 2/3; so a radiance cosθ gives irradiance π·2/3 = ∫cos²θ dω).
double cosineError(int size) {
  const SensorMap map(size);
  double cosine = 0;
  for (size_t k = 0; k < map.texels(); ++k) cosine += map.weight() * map.direction(k).z;
  return cosine - 2.0 / 3.0;
}

TEST(SensorMap, DirectionsAreUnitOnTheHemisphereAndCosineDistributed) {
  const SensorMap map(48);
  double cosineSquared = 0, x = 0, lowest = 1;
  for (size_t k = 0; k < map.texels(); ++k) {
    const Vec3& d = map.direction(k);
    EXPECT_NEAR(glm::length(d), 1.0, 1e-12);
    EXPECT_GE(d.z, 0.0);
    cosineSquared += map.weight() * d.z * d.z;
    x += map.weight() * d.x;
    lowest = std::min(lowest, d.z);
  }
  EXPECT_NEAR(cosineSquared, 0.5, 1e-3);  // E[cos²θ] = 1/2
  EXPECT_NEAR(x, 0.0, 1e-12);             // no side favoured
  // The quadrature converges (the rim, where cosθ = √(1 − r²) is not smooth, is its error).
  EXPECT_LT(std::abs(cosineError(48)), 3e-3);
  EXPECT_LT(std::abs(cosineError(96)), 0.6 * std::abs(cosineError(48)));
  EXPECT_LT(std::abs(cosineError(16)), 1e-2);
  // The rim is reached: the paper's 135° camera misses every direction below 22.5°.
  EXPECT_LT(lowest, std::sin(M_PI / 8));
}

TEST(SensorMap, SizesOutOfRangeAreRefused) {
  EXPECT_THROW(SensorMap(0), std::invalid_argument);
  EXPECT_THROW(SensorMap(SensorMap::kMaxSize + 1), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::gi
