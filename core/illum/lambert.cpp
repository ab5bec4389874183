#include "core/illum/lambert.h"

#include <cmath>

namespace penumbra {

double lambertIntegral(const Vec3& p, const Vec3& n, const Polygon3& polygon) {
  const size_t count = polygon.size();
  if (count < 3) return 0;
  // Lambert: Φ = ½ Σ_i Θ_i (n · Γ_i), Θ_i the angle each edge subtends at p and Γ_i
  // the unit normal of the plane through p and the edge. The sign only tells the
  // winding as seen from p, and the integrand is non-negative in front of p's
  // plane, so the magnitude is the value.
  double sum = 0;
  for (size_t i = 0; i < count; ++i) sum += lambertEdgeTerm(p, n, polygon[(i + count - 1) % count], polygon[i]);
  return 0.5 * std::abs(sum);
}

double lambertEdgeTerm(const Vec3& p, const Vec3& n, const Vec3& a, const Vec3& b) {
  const Vec3 pa = a - p, pb = b - p;
  const Vec3 normal = glm::cross(pa, pb);
  const double sine = glm::length(normal);  // |a||b| sin Θ
  return sine > 0 ? std::atan2(sine, glm::dot(pa, pb)) * glm::dot(n, normal) / sine : 0.0;
}

}  // namespace penumbra
