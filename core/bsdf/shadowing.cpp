#include "core/bsdf/shadowing.h"

#include <cmath>

namespace penumbra::bsdf {

double g2Uncorrelated(const Microsurface& s, const Vec3& wi, const Vec3& wo) {
  return s.g1Dist(wi) * s.g1Dist(wo);
}

double g2Correlated(const Microsurface& s, const Vec3& wi, const Vec3& wo) {
  if (wo.z <= 0) return 0;
  // -Λ(-wi) = 1 + Λ(wi) for wi above: both cases are 1 / (|1 + Λ(wi)| + Λ(wo)).
  const double c = 1.0 / s.g1Dist(wi);
  return 1.0 / (c + s.lambdaUp(wo));
}

double g2Middle(const Microsurface& s, const Vec3& wi, const Vec3& wo) {
  if (wo.z <= 0) return s.g1Dist(wi);  // eq. 14: a ray leaving downwards always hits
  return s.g1Dist(wi) - g2Correlated(s, wi, wo);
}

double escapeReflected(const Microsurface& s, HeightModel model, const Vec3& w, const Vec3& d) {
  if (d.z <= 0) return 0;
  if (model == HeightModel::Uncorrelated) return s.g1Dist(d);
  const double c = 1.0 / s.g1Dist(w), l = s.lambdaUp(d);
  if (std::isinf(c)) return std::isinf(l) ? 0.0 : 1.0;  // arrived grazing: at the top
  return c / (c + l);
}

double escapeTransmitted(const Microsurface& s, HeightModel model, const Vec3& w, const Vec3& d) {
  if (d.z <= 0) return 0;
  if (model == HeightModel::Uncorrelated) return s.g1Dist(d);
  const double c = 1.0 / s.g1Dist(w), l = s.lambdaUp(d);
  if (std::isinf(l)) return 0;
  if (std::isinf(c)) return 0;  // arrived grazing: at the very top, the bottom is out of reach
  // c B(c, 1 + l) = Γ(c + 1) Γ(1 + l) / Γ(c + 1 + l), in logs for large c.
  return std::exp(std::lgamma(c + 1.0) + std::lgamma(1.0 + l) - std::lgamma(c + 1.0 + l));
}

}  // namespace penumbra::bsdf
