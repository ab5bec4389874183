// A sensor's map (seed 001, "Sensor"): size × size texels, each a direction over the hemisphere
// around a surface normal and a weight F_ij, the texel's share of the projected solid angle.
//
// The paper's sensor is a 135° perspective camera: it cannot see the hemisphere's rim, and
// light from grazing directions is lost (a 135° square frustum covers 88% of the projected
// solid angle, so 12% of the irradiance of a uniformly lit point). Here the whole hemisphere is
// covered: the square maps onto the unit disc by the concentric map of Shirley & Chiu and the
// disc lifts to the hemisphere (Malley). The concentric map keeps areas (Jacobian π/4), and a
// disc region's area is the projected solid angle of its lift, so every texel has the same
// weight F_ij = 1/size² (checked against the texels' areas in tests/core/gi).
//
// A sensor casts one ray per texel, except in the outer rings of the square (the rim of the
// disc: directions within ~20° of the horizon at 32²), whose texels are split rimSplit ×
// rimSplit, each part its own ray with its share of the weight. A point that sees light only
// near its horizon (a box top under a dark ceiling) otherwise takes the whole band from a ring
// or two of fixed directions, the same for every sensor: a bias, not noise (cubes15's box tops
// −2.9 % at 32², −9.9 % at 16², −0.85 % at 64²; docs/RENDERING.md "Where sensor GI is biased").
// Immutable after construction; thread-safe.
#pragma once

#include <vector>

#include "core/geom/vec.h"

namespace penumbra::gi {

// The concentric map of the square [-1, 1]² onto the unit disc (area-preserving up to π/4).
Vec2 concentricDisc(const Vec2& square);

// One ray a sensor casts: a direction in the normal's frame (z along the normal; unit) and its
// share of the projected solid angle / π.
struct SensorRay {
  Vec3 direction{0.0, 0.0, 1.0};
  double weight = 0;
};

class SensorMap {
 public:
  static constexpr int kMaxSize = 256;
  static constexpr int kRimRings = 2, kRimSplit = 4;
  // size: texels per side, 1..kMaxSize (std::invalid_argument otherwise); the outer rimRings
  // rings of texels are cast as rimSplit² rays each (1: one ray per texel everywhere).
  explicit SensorMap(int size, int rimRings = kRimRings, int rimSplit = kRimSplit);

  int size() const { return size_; }
  size_t texels() const { return directions_.size(); }
  // Texel k's direction: the lifted centroid of its disc image, in the normal's frame (z along
  // the normal; unit).
  const Vec3& direction(size_t k) const { return directions_[k]; }
  // F_ij of texel k: its projected solid angle / π (the weights sum to 1).
  double weight() const { return weight_; }
  // What a sensor casts; the weights sum to 1.
  const std::vector<SensorRay>& rays() const { return rays_; }

 private:
  int size_ = 0;
  double weight_ = 0;
  std::vector<Vec3> directions_;  // row-major, texel k = i·size + j
  std::vector<SensorRay> rays_;
};

}  // namespace penumbra::gi
