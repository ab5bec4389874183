// Stratified points on a light polygon: the unit square cut into n×n strata, one jittered
// point in each, carried onto the polygon by a measure-preserving map (fan triangles chosen
// by area, then the square-root map onto the triangle). Immutable; thread-safe.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/geom/polygon.h"

namespace penumbra {

class LightSampler {
 public:
  explicit LightSampler(const Polygon3& polygon) : apex_(polygon.empty() ? Vec3(0.0) : polygon[0]) {
    cumulative_.push_back(0);
    for (size_t k = 1; k + 1 < polygon.size(); ++k) {
      edgeA_.push_back(polygon[k] - polygon[0]);
      edgeB_.push_back(polygon[k + 1] - polygon[k]);
      area_ += 0.5 * glm::length(glm::cross(polygon[k] - polygon[0], polygon[k + 1] - polygon[0]));
      cumulative_.push_back(area_);
    }
    if (area_ > 0)
      for (double& c : cumulative_) c /= area_;
  }

  double area() const { return area_; }

  // The point for (u1, u2) in the unit square; uniform (u1, u2) give uniform points.
  Vec3 point(double u1, double u2) const {
    if (!(area_ > 0)) return apex_;
    const size_t last = edgeA_.size() - 1;
    size_t k = size_t(std::upper_bound(cumulative_.begin() + 1, cumulative_.end(), u1) -
                      (cumulative_.begin() + 1));
    k = std::min(k, last);
    const double share = cumulative_[k + 1] - cumulative_[k];
    const double s = share > 0 ? std::clamp((u1 - cumulative_[k]) / share, 0.0, 1.0) : 0.0;
    const double a = std::sqrt(s);
    return apex_ + a * edgeA_[k] + (a * u2) * edgeB_[k];
  }

  // Stratum (i, j) of an n×n grid with jitter (ju, jv) in [0, 1)².
  Vec3 stratified(int i, int j, int n, double ju, double jv) const {
    return point((i + ju) / n, (j + jv) / n);
  }

 private:
  Vec3 apex_;
  std::vector<Vec3> edgeA_, edgeB_;  // per fan triangle: v_k − v0, v_k+1 − v_k
  std::vector<double> cumulative_;   // area fractions, [0] = 0, back() = 1
  double area_ = 0;
};

}  // namespace penumbra
