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

}  // namespace penumbra::bsdf
