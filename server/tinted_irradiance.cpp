#include "server/tinted_irradiance.h"

#include <cmath>
#include <limits>

namespace penumbra::server::mesh_binary {

namespace {

// Whether `decoded` may stand for the f32 channel `sent`: equal, or within 2 units in the last
// place of `sent` (the spacing of f32 values just above |sent|). Why 2 is honest, not slack, when
// the vertex is truly the tint scaled (e_c = e_k · t exactly): f32(v)·f32(t) is within 1.5 ulps of
// the exact product ((m_v + m_t) / 2 ≤ 1.5 for their significands m in [1, 2)), rounding it to f32
// adds at most half an ulp, and f32(e_c) is within half an ulp of e_c: two f32 values less than
// 2.5 ulps apart are at most 2 apart. NaN never fits; infinity fits only itself.
bool fits(float decoded, float sent) {
  if (decoded == sent) return true;
  const double magnitude = std::fabs(double(sent));
  const double ulp = double(std::nextafter(float(magnitude), std::numeric_limits<float>::infinity())) - magnitude;
  return std::fabs(double(decoded) - double(sent)) <= 2.0 * ulp;
}

}  // namespace

TintedIrradiance tintIrradiance(const std::vector<Vec3>& irradiance) {
  // The brightest vertex's largest channel: k, and the tint its colour over that channel.
  size_t brightest = 0;
  int k = 0;
  double peak = 0.0;
  for (size_t i = 0; i < irradiance.size(); ++i)
    for (int c = 0; c < 3; ++c)
      if (irradiance[i][c] > peak) peak = irradiance[i][c], brightest = i, k = c;
  TintedIrradiance out;
  out.channels = 1;
  if (peak > 0.0 && std::isfinite(peak))
    for (int c = 0; c < 3; ++c) out.tint[c] = c == k ? 1.0f : float(irradiance[brightest][c] / peak);

  // Each vertex's value in channel k, kept while every channel decodes (an f32 product, as a
  // page's Float32Array stores a JavaScript product of two f32 values: that product is exact in
  // a double) within the bound of `fits`.
  out.values.reserve(irradiance.size());
  for (const Vec3& e : irradiance) {
    const float v = float(e[k]);
    for (int c = 0; c < 3 && out.channels == 1; ++c)
      if (!fits(v * out.tint[c], float(e[c]))) out.channels = 3;
    if (out.channels == 3) break;
    out.values.push_back(v);
  }
  if (out.channels == 1) return out;

  out.tint = {1.0f, 1.0f, 1.0f};
  out.values.clear();
  out.values.reserve(3 * irradiance.size());
  for (const Vec3& e : irradiance)
    for (int c = 0; c < 3; ++c) out.values.push_back(float(e[c]));
  return out;
}

}  // namespace penumbra::server::mesh_binary
