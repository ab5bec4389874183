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
// Immutable after construction; thread-safe.
#pragma once

#include <vector>

#include "core/geom/vec.h"

namespace penumbra::gi {

// The concentric map of the square [-1, 1]² onto the unit disc (area-preserving up to π/4).
Vec2 concentricDisc(const Vec2& square);

class SensorMap {
 public:
  static constexpr int kMaxSize = 256;
  // size: texels per side, 1..kMaxSize (std::invalid_argument otherwise).
  explicit SensorMap(int size);

  int size() const { return size_; }
  size_t texels() const { return directions_.size(); }
  // Texel k's direction: the lifted centroid of its disc image, in the normal's frame (z along
  // the normal; unit).
  const Vec3& direction(size_t k) const { return directions_[k]; }
  // F_ij of texel k: its projected solid angle / π (the weights sum to 1).
  double weight() const { return weight_; }

 private:
  int size_ = 0;
  double weight_ = 0;
  std::vector<Vec3> directions_;  // row-major, texel k = i·size + j
};

}  // namespace penumbra::gi
