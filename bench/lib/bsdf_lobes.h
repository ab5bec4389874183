// Per-bounce lobes of the position-free walk (core/bsdf) and of the height-sampling reference
// (heitz_walk.h) as direction histograms, and the statistics that compare them. Pure; thread-safe.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bench/lib/heitz_walk.h"
#include "core/bsdf/walk.h"

namespace penumbra::bench {

// Histograms of exit energy per bounce order (1, 2, ..., kOrders where the last holds the rest),
// over bins uniform in cos θ (nz over [-1, 1]) and φ (nphi), each divided by the number of walks.
struct Lobes {
  static constexpr int kOrders = 3;
  int nz = 12, nphi = 12;
  std::vector<std::vector<double>> energy;  // [order][bin]
  int walks = 0;
  int bin(const glm::dvec3& d) const;
  double reflected(int order) const;    // energy leaving above the macrosurface
  double transmitted(int order) const;  // below
};

// A configuration of the supplement's figures: facets, GGX alpha, incident angle θ (rad, from
// the macro normal, azimuth 0).
struct LobeConfig {
  bsdf::Facets facets = bsdf::Facets::Conductor;
  double alphaX = 1, alphaY = 1;
  double theta = 0;
  std::string name() const;
};

bsdf::WalkParams walkParams(const LobeConfig& c, bsdf::HeightModel height, bool single = false);
Lobes walkLobes(const LobeConfig& c, bsdf::HeightModel height, int walks, uint64_t seed);
Lobes heitzLobes(const LobeConfig& c, int walks, uint64_t seed);

// Σ|a - b| / Σ b over the bins of one order (b: the reference), and the value two independent
// Poisson histograms of the reference's size would give by noise alone (Σ sqrt(4 b_i N / π) / (N Σ b)).
double relativeL1(const Lobes& a, const Lobes& b, int order);
double relativeL1Noise(const Lobes& b, int order);
// Two-sample chi-square over bins with at least 10 counts in the sum (unit weights: counts =
// energy × walks); dof receives the bins used minus one.
double twoSampleChiSquare(const Lobes& a, const Lobes& b, int order, int& dof);

}  // namespace penumbra::bench
