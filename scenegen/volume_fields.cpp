#include "scenegen/volume_fields.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace penumbra {

namespace {

// Lattice value noise: a hashed value in [0, 1] per integer point, smoothly interpolated.
double latticeValue(glm::ivec3 p, uint64_t seed) {
  uint64_t h = seed * 0x9E3779B97F4A7C15ull;
  for (int a = 0; a < 3; ++a) {
    h ^= uint64_t(uint32_t(p[a])) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 31;
  }
  return double(h >> 11) * 0x1.0p-53;
}

double valueNoise(const Vec3& p, uint64_t seed) {
  const glm::ivec3 base(glm::floor(p));
  const Vec3 f = p - Vec3(base);
  const Vec3 w = f * f * (3.0 - 2.0 * f);  // smoothstep weights
  double sum = 0.0;
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 o((c >> 2) & 1, (c >> 1) & 1, c & 1);
    const double weight = (o.x ? w.x : 1 - w.x) * (o.y ? w.y : 1 - w.y) * (o.z ? w.z : 1 - w.z);
    sum += weight * latticeValue(base + o, seed);
  }
  return sum;
}

double fractalNoise(const Vec3& p, uint64_t seed, int octaves) {
  double sum = 0.0, amplitude = 0.5, frequency = 1.0;
  for (int i = 0; i < octaves; ++i, amplitude *= 0.5, frequency *= 2.0)
    sum += amplitude * valueNoise(p * frequency, seed + uint64_t(i));
  return sum / (1.0 - std::pow(0.5, octaves));  // back to [0, 1]
}

// Marschner & Lobb (1994) on [−1, 1]³: f_M = 6, α = 0.25.
double marschnerLobb(const Vec3& p) {
  constexpr double kPi = std::numbers::pi, fM = 6.0, alpha = 0.25;
  const double r = std::sqrt(p.x * p.x + p.y * p.y);
  const double rho = std::cos(2.0 * kPi * fM * std::cos(kPi * r / 2.0));
  return (1.0 - std::sin(kPi * p.z / 2.0) + alpha * (1.0 + rho)) / (2.0 * (1.0 + alpha));
}

// A plume of fractal noise: dense near a vertical axis, empty outside (sparse, like smoke).
double smoke(const Vec3& u, uint64_t seed) {
  const double radial = std::hypot(u.x - 0.5, u.z - 0.5) / (0.18 + 0.2 * u.y);
  const double envelope = std::max(0.0, 1.0 - radial * radial) * std::min(1.0, 4.0 * u.y);
  const double density = fractalNoise(u * 6.0, seed, 5) * envelope;
  return std::clamp((density - 0.25) * 2.5, 0.0, 1.0);
}

// Heavy fluid (1) under light (0): a multi-mode interface rolled up by 3D noise, sharp to
// about one voxel (a Richtmyer–Meshkov-like mixing layer).
double mixingLayer(const Vec3& u, uint64_t seed, double voxel) {
  constexpr double kTau = 2.0 * std::numbers::pi;
  const double modes = 0.05 * std::sin(kTau * 2 * u.x) * std::cos(kTau * 3 * u.y) +
                       0.03 * std::sin(kTau * 5 * u.x + 1.0) * std::sin(kTau * 4 * u.y + 2.0);
  const double rollup = 0.12 * (fractalNoise(u * 8.0, seed, 4) - 0.5);
  const double height = 0.5 + modes + rollup;
  return std::clamp(0.5 - (u.z - height) / (2.0 * voxel), 0.0, 1.0);
}

template <class T>
volume::DenseGrid<T> quantise(const volume::DenseGrid<float>& field, double top) {
  volume::DenseGrid<T> out(field.size);
  for (size_t i = 0; i < field.values.size(); ++i)
    out.values[i] = T(std::lround(std::clamp(double(field.values[i]), 0.0, 1.0) * top));
  return out;
}

}  // namespace

std::string volumeFieldName(VolumeField field) {
  switch (field) {
    case VolumeField::MarschnerLobb:
      return "marschner-lobb";
    case VolumeField::Sphere:
      return "sphere";
    case VolumeField::Smoke:
      return "smoke";
    case VolumeField::MixingLayer:
      return "mixing";
  }
  return "?";
}

SphereGeometry sphereGeometry(glm::ivec3 size) {
  const int n = std::max({size.x, size.y, size.z});
  const Vec3 centre = Vec3(size - 1) * 0.5;
  const double radius = 0.35 * double(std::min({size.x, size.y, size.z}) - 1);
  return {centre, radius, 1.0 / (2.0 * n)};
}

volume::DenseGrid<float> makeVolumeField(const VolumeFieldSpec& spec) {
  volume::DenseGrid<float> out(spec.size);
  const Vec3 last = Vec3(glm::max(spec.size - 1, glm::ivec3(1)));
  const SphereGeometry sphere = sphereGeometry(spec.size);
  const double voxel = 1.0 / double(std::max({spec.size.x, spec.size.y, spec.size.z}));
  for (int z = 0; z < spec.size.z; ++z)
    for (int y = 0; y < spec.size.y; ++y)
      for (int x = 0; x < spec.size.x; ++x) {
        const Vec3 p(x, y, z), u = p / last;  // u in [0, 1]³
        double v = 0.0;
        switch (spec.field) {
          case VolumeField::MarschnerLobb:
            v = marschnerLobb(u * 2.0 - 1.0);
            break;
          case VolumeField::Sphere:
            v = 0.5 + (sphere.radius - glm::length(p - sphere.centre)) * sphere.valuePerVoxel;
            break;
          case VolumeField::Smoke:
            v = smoke(u, spec.seed);
            break;
          case VolumeField::MixingLayer:
            v = mixingLayer(u, spec.seed, voxel);
            break;
        }
        out[{x, y, z}] = float(v);
      }
  return out;
}

volume::DenseGrid<uint8_t> quantise8(const volume::DenseGrid<float>& field) {
  return quantise<uint8_t>(field, 255.0);
}
volume::DenseGrid<uint16_t> quantise16(const volume::DenseGrid<float>& field) {
  return quantise<uint16_t>(field, 65535.0);
}

}  // namespace penumbra
