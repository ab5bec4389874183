#include "bench/lib/gi_path_tracer.h"

#include <cmath>
#include <optional>

namespace penumbra::bench {

namespace {

// Distance along the unit ray to the front of a light polygon (convex, CCW seen from its front).
std::optional<double> lightDistance(const Light& light, const Vec3& p, const Vec3& d) {
  const Vec3& a = light.polygon[0];
  const Vec3 normal = glm::normalize(glm::cross(light.polygon[1] - a, light.polygon[2] - a));
  const double facing = glm::dot(normal, d);
  if (facing >= 0) return std::nullopt;
  const double t = glm::dot(normal, a - p) / facing;
  if (t < 0) return std::nullopt;
  const Vec3 x = p + t * d;
  for (size_t k = 0; k < light.polygon.size(); ++k) {
    const Vec3& u = light.polygon[k];
    const Vec3& v = light.polygon[(k + 1) % light.polygon.size()];
    if (glm::dot(glm::cross(v - u, x - u), normal) < 0) return std::nullopt;
  }
  return t;
}

}  // namespace

PathTracedIndirect pathTracedIndirect(const Scene& scene, const RayScene& rays, const MeshLookup& direct,
                                      const Vec3& p, const Vec3& n, int samples, std::mt19937_64& rng) {
  const DirectLight lookup = [&](uint32_t faceIndex, const Vec3& q) {
    return direct.irradiance(faceIndex, q).value_or(Vec3(0.0));
  };
  return pathTracedIndirect(scene, rays, lookup, p, n, samples, rng);
}

PathTracedIndirect pathTracedIndirect(const Scene& scene, const RayScene& rays, const DirectLight& direct,
                                      const Vec3& p, const Vec3& n, int samples, std::mt19937_64& rng) {
  // Any orthonormal pair perpendicular to n.
  const Vec3 helper = std::abs(n.x) < 0.5 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  const Vec3 u = glm::normalize(glm::cross(n, helper));
  const Vec3 v = glm::cross(n, u);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double tNear = 1e-6 * glm::length(scene.bounds().max - scene.bounds().min);
  Vec3 sum(0.0), sumSquares(0.0);
  for (int s = 0; s < samples; ++s) {
    // Malley: a uniform point of the unit disc (by rejection), lifted to the hemisphere.
    double x, y;
    do {
      x = 2 * unit(rng) - 1;
      y = 2 * unit(rng) - 1;
    } while (x * x + y * y >= 1);
    const Vec3 d = glm::normalize(x * u + y * v + std::sqrt(1 - x * x - y * y) * n);
    Vec3 radiance(0.0);
    const auto hit = rays.intersectFront(p, d, tNear);
    double lightT = INFINITY;
    for (const Light& light : scene.lights())
      if (const auto t = lightDistance(light, p, d)) lightT = std::min(lightT, *t);
    if (hit && hit->t < lightT)
      radiance = scene.albedo(hit->face) / M_PI * direct(hit->faceIndex, hit->position);
    // E = ∫ L cosθ dω = π · E_cosine-pdf[L].
    const Vec3 e = M_PI * radiance;
    sum += e;
    sumSquares += e * e;
  }
  PathTracedIndirect out;
  out.mean = sum / double(samples);
  const Vec3 variance = glm::max(sumSquares / double(samples) - out.mean * out.mean, Vec3(0.0));
  out.stdError = glm::sqrt(variance / double(samples));
  return out;
}

}  // namespace penumbra::bench
