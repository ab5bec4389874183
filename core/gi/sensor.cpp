#include "core/gi/sensor.h"

#include <cmath>

#include "core/geom/plane_frame.h"
#include "core/raycast/light_hit.h"

namespace penumbra::gi {

Sensor::Sensor(const Scene& scene, const RayScene& rays, const SensorMap& map, OutgoingRadianceFn outgoing)
    : scene_(scene), rays_(rays), map_(map), outgoing_(std::move(outgoing)) {
  for (const Light& light : scene.lights()) lightPlanes_.push_back(light.plane());
  // Rays start on the face's plane; the face itself is seen from behind (passed through) and
  // faces meeting it at an edge are not hit before this distance (Tolerance::onPlane()).
  tNear_ = scene.tolerance().onPlane();
}

Vec3 Sensor::incoming(const Vec3& p, const Vec3& dir) const {
  const auto hit = rays_.intersectFront(p, dir, tNear_);
  const auto light = closestLightHit(scene_.lights(), lightPlanes_, p, dir, hit ? hit->t : INFINITY);
  if (light && (!hit || light->t < hit->t)) return Vec3(0.0);
  if (!hit) return Vec3(0.0);
  return outgoing_(*hit);
}

Vec3 Sensor::irradiance(const Vec3& p, const Vec3& n) const {
  const PlaneFrame frame = PlaneFrame::onPlane(Plane::throughPoint(n, p), p);
  Vec3 sum(0.0);
  for (const SensorRay& ray : map_.rays()) {
    const Vec3& d = ray.direction;
    sum += ray.weight * incoming(p, d.x * frame.u + d.y * frame.v + d.z * frame.normal);
  }
  return M_PI * sum;
}

OutgoingRadianceFn diffuseOutgoing(const Scene& scene,
                                   std::function<Vec3(uint32_t faceIndex, const Vec3& q)> irradiance) {
  return [&scene, irradiance = std::move(irradiance)](const RayScene::Hit& hit) {
    if (!hit.frontFacing) return Vec3(0.0);
    return scene.albedo(hit.face) / M_PI * irradiance(hit.faceIndex, hit.position);
  };
}

}  // namespace penumbra::gi
