// Embree Monte Carlo estimator of the same irradiance as ExactReference:
// area sampling of each light (optionally stratified), occlusion rays with the
// single-sided blocking rule. Seeded and deterministic per (seed, point index);
// evaluateMany runs points in parallel with TBB. Immutable after construction;
// thread-safe.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/scene/scene.h"

namespace penumbra {

struct MonteCarloEstimate {
  Vec3 irradiance{0.0};
  Vec3 standardError{0.0};  // of the irradiance estimate, per channel
};

struct MonteCarloOptions {
  int samplesPerLight = 256;
  uint64_t seed = 1;
  bool stratified = false;  // jittered grids over the light: 16 replicas of N/16 (monte_carlo.cpp)
};

class RayScene;

class MonteCarloEstimator {
 public:
  explicit MonteCarloEstimator(const Scene& scene);
  ~MonteCarloEstimator();

  MonteCarloEstimate estimate(const Vec3& p, const Vec3& n, const MonteCarloOptions& options,
                              uint64_t pointIndex = 0) const;
  std::vector<MonteCarloEstimate> estimateMany(const std::vector<Vec3>& points,
                                               const std::vector<Vec3>& normals,
                                               const MonteCarloOptions& options) const;

 private:
  const Scene& scene_;
  std::unique_ptr<RayScene> rays_;
};

}  // namespace penumbra
