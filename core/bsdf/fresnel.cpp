#include "core/bsdf/fresnel.h"

#include <algorithm>
#include <cmath>
#include <complex>

namespace penumbra::bsdf {

double fresnelDielectric(double cosI, double eta) {
  cosI = std::clamp(cosI, 0.0, 1.0);
  const double sin2T = (1.0 - cosI * cosI) / (eta * eta);
  if (sin2T >= 1.0) return 1.0;
  const double cosT = std::sqrt(1.0 - sin2T);
  const double rs = (cosI - eta * cosT) / (cosI + eta * cosT);
  const double rp = (eta * cosI - cosT) / (eta * cosI + cosT);
  return 0.5 * (rs * rs + rp * rp);
}

double fresnelConductor(double cosI, double eta, double k) {
  using C = std::complex<double>;
  cosI = std::clamp(cosI, 0.0, 1.0);
  const C n(eta, k);
  const C cosT = std::sqrt(C(1.0) - (1.0 - cosI * cosI) / (n * n));
  const C rs = (cosI - n * cosT) / (cosI + n * cosT);
  const C rp = (n * cosI - cosT) / (n * cosI + cosT);
  return 0.5 * (std::norm(rs) + std::norm(rp));
}

Vec3 fresnelConductor(double cosI, const Vec3& eta, const Vec3& k) {
  return {fresnelConductor(cosI, eta.x, k.x), fresnelConductor(cosI, eta.y, k.y),
          fresnelConductor(cosI, eta.z, k.z)};
}

std::optional<Vec3> refract(const Vec3& w, const Vec3& m, double eta) {
  const double cosI = glm::dot(w, m);
  const double sin2T = (1.0 - cosI * cosI) / (eta * eta);
  if (sin2T >= 1.0) return std::nullopt;
  const double cosT = std::sqrt(1.0 - sin2T);
  return glm::normalize(-w / eta + (cosI / eta - cosT) * m);
}

}  // namespace penumbra::bsdf
