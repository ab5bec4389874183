// Statistics for the BSDF tests: chi-square thresholds and direction histograms over
// (cos θ, φ) bins. Plain functions; no state.
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

#include <glm/glm.hpp>

namespace penumbra::bsdf::test {

// The chi-square value exceeded with probability ~1e-4 under the null (Wilson-Hilferty).
inline double chiSquareThreshold(int dof) {
  const double z = 3.719;  // standard normal quantile 1 - 1e-4
  const double k = dof, c = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - c + z * std::sqrt(c), 3.0);
}

// Bins uniform in cos θ over [zMin, zMax] and in φ over [0, 2π).
struct SphereBins {
  int nz = 16, nphi = 16;
  double zMin = -1, zMax = 1;
  int size() const { return nz * nphi; }
  int index(const glm::dvec3& d) const {
    if (d.z < zMin || d.z >= zMax) return -1;
    const int i = std::min(nz - 1, int((d.z - zMin) / (zMax - zMin) * nz));
    double phi = std::atan2(d.y, d.x);
    if (phi < 0) phi += 2 * std::numbers::pi;
    const int j = std::min(nphi - 1, int(phi / (2 * std::numbers::pi) * nphi));
    return i * nphi + j;
  }
  // ∫_bin f(d) dd by the midpoint rule with sub × sub points (f: density per solid angle).
  template <class F>
  std::vector<double> integrate(F&& f, int sub = 8) const {
    std::vector<double> out(size(), 0.0);
    const double dz = (zMax - zMin) / nz, dphi = 2 * std::numbers::pi / nphi;
    for (int i = 0; i < nz; ++i)
      for (int j = 0; j < nphi; ++j) {
        double sum = 0;
        for (int a = 0; a < sub; ++a)
          for (int b = 0; b < sub; ++b) {
            const double z = zMin + (i + (a + 0.5) / sub) * dz, phi = (j + (b + 0.5) / sub) * dphi;
            const double r = std::sqrt(std::max(0.0, 1 - z * z));
            sum += f(glm::dvec3(r * std::cos(phi), r * std::sin(phi), z));
          }
        out[i * nphi + j] = sum * dz * dphi / (sub * sub);
      }
    return out;
  }
};

// Pearson's chi-square of observed counts against expected counts; bins expecting fewer than
// 5 are pooled into one. dof receives the number of pooled bins minus one.
inline double chiSquare(const std::vector<double>& observed, const std::vector<double>& expected, int& dof) {
  double chi = 0, poolObs = 0, poolExp = 0;
  int bins = 0;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] < 5) {
      poolObs += observed[i];
      poolExp += expected[i];
      continue;
    }
    chi += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++bins;
  }
  if (poolExp >= 5) {
    chi += (poolObs - poolExp) * (poolObs - poolExp) / poolExp;
    ++bins;
  }
  dof = bins - 1;
  return chi;
}

}  // namespace penumbra::bsdf::test
