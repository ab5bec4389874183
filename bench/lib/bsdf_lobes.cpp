#include "bench/lib/bsdf_lobes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

namespace penumbra::bench {

int Lobes::bin(const glm::dvec3& d) const {
  const int i = std::clamp(int((d.z + 1.0) * 0.5 * nz), 0, nz - 1);
  double phi = std::atan2(d.y, d.x);
  if (phi < 0) phi += 2 * std::numbers::pi;
  const int j = std::clamp(int(phi / (2 * std::numbers::pi) * nphi), 0, nphi - 1);
  return i * nphi + j;
}

double Lobes::reflected(int order) const {
  double sum = 0;
  for (int i = nz / 2; i < nz; ++i)
    for (int j = 0; j < nphi; ++j) sum += energy[order][i * nphi + j];
  return sum;
}

double Lobes::transmitted(int order) const {
  double sum = 0;
  for (int i = 0; i < nz / 2; ++i)
    for (int j = 0; j < nphi; ++j) sum += energy[order][i * nphi + j];
  return sum;
}

std::string LobeConfig::name() const {
  static const char* facets[] = {"rough diffuse", "conductor", "dielectric"};
  char buf[128];
  std::snprintf(buf, sizeof buf, "%s alpha (%.2g, %.2g) theta %.1f", facets[int(this->facets)], alphaX, alphaY, theta);
  return buf;
}

bsdf::WalkParams walkParams(const LobeConfig& c, bsdf::HeightModel height, bool single) {
  bsdf::WalkParams p;
  p.surface = bsdf::Microsurface{bsdf::Ndf::GGX, c.alphaX, c.alphaY};
  p.facets = c.facets;
  p.height = height;
  p.unitFresnel = true;
  p.singleScattering = single;
  return p;
}

namespace {

Lobes emptyLobes() {
  Lobes l;
  l.energy.assign(Lobes::kOrders, std::vector<double>(l.nz * l.nphi, 0.0));
  return l;
}

glm::dvec3 incident(double theta) { return {std::sin(theta), 0.0, std::cos(theta)}; }

}  // namespace

Lobes walkLobes(const LobeConfig& c, bsdf::HeightModel height, int walks, uint64_t seed) {
  Lobes l = emptyLobes();
  l.walks = walks;
  const bsdf::WalkParams p = walkParams(c, height);
  bsdf::Rng rng(seed);
  for (int i = 0; i < walks; ++i) {
    const std::optional<bsdf::WalkExit> e = bsdf::sampleWalk(p, incident(c.theta), rng);
    if (!e) continue;
    l.energy[std::min(e->bounces, Lobes::kOrders) - 1][l.bin(e->direction)] += e->weight.x / walks;
  }
  return l;
}

Lobes heitzLobes(const LobeConfig& c, int walks, uint64_t seed) {
  Lobes l = emptyLobes();
  l.walks = walks;
  HeitzSurface s;
  s.alphaX = c.alphaX;
  s.alphaY = c.alphaY;
  s.kind = c.facets == bsdf::Facets::Conductor  ? HeitzSurface::Kind::Conductor
           : c.facets == bsdf::Facets::Dielectric ? HeitzSurface::Kind::Dielectric
                                                  : HeitzSurface::Kind::Diffuse;
  std::mt19937_64 gen(seed);
  for (int i = 0; i < walks; ++i) {
    const std::optional<HeitzExit> e = heitzWalk(s, incident(c.theta), gen);
    if (!e) continue;
    l.energy[std::min(e->bounces, Lobes::kOrders) - 1][l.bin(e->direction)] += 1.0 / walks;
  }
  return l;
}

double relativeL1(const Lobes& a, const Lobes& b, int order) {
  double diff = 0, ref = 0;
  for (size_t i = 0; i < b.energy[order].size(); ++i) {
    diff += std::abs(a.energy[order][i] - b.energy[order][i]);
    ref += b.energy[order][i];
  }
  return ref > 0 ? diff / ref : 0.0;
}

double relativeL1Noise(const Lobes& b, int order) {
  double noise = 0, ref = 0;
  for (double e : b.energy[order]) {
    noise += std::sqrt(4.0 * e * b.walks / std::numbers::pi);
    ref += e * b.walks;
  }
  return ref > 0 ? noise / ref : 0.0;
}

double twoSampleChiSquare(const Lobes& a, const Lobes& b, int order, int& dof) {
  double chi = 0;
  int bins = 0;
  for (size_t i = 0; i < b.energy[order].size(); ++i) {
    const double x = a.energy[order][i] * a.walks, y = b.energy[order][i] * b.walks;
    if (x + y < 10) continue;
    chi += (x - y) * (x - y) / (x + y);
    ++bins;
  }
  dof = bins - 1;
  return chi;
}

}  // namespace penumbra::bench
