#include "core/raycast/light_hit.h"

namespace penumbra {

std::optional<double> frontLightHit(const Light& light, const Plane& plane, const Vec3& origin,
                                    const Vec3& dir) {
  const double facing = glm::dot(plane.normal, dir);
  if (!(facing < 0)) return std::nullopt;  // seen from behind or edge-on: lights emit forward only
  const double t = -plane.signedDistance(origin) / facing;
  if (!(t >= 0)) return std::nullopt;
  const Vec3 x = origin + t * dir;
  const Polygon3& polygon = light.polygon;
  for (size_t k = 0; k < polygon.size(); ++k) {
    const Vec3& a = polygon[k];
    const Vec3& b = polygon[(k + 1) % polygon.size()];
    if (glm::dot(glm::cross(b - a, x - a), plane.normal) < 0) return std::nullopt;
  }
  return t;
}

std::optional<LightHit> closestLightHit(const std::vector<Light>& lights, const std::vector<Plane>& planes,
                                        const Vec3& origin, const Vec3& dir, double tMax) {
  std::optional<LightHit> closest;
  for (size_t l = 0; l < lights.size(); ++l) {
    const auto t = frontLightHit(lights[l], planes[l], origin, dir);
    if (t && *t <= tMax && (!closest || *t < closest->t)) closest = LightHit{l, *t};
  }
  return closest;
}

}  // namespace penumbra
