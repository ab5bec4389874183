#include "core/render/volume_lighting.h"

#include <algorithm>

namespace penumbra {

VolumeLighting::VolumeLighting(const Scene& scene, const RayScene& rays, int strata)
    : scene_(scene), rays_(rays), strata_(std::max(1, strata)) {
  for (const Light& light : scene.lights()) {
    samplers_.emplace_back(light.polygon);
    lightPlanes_.push_back(light.plane());
  }
}

template <class Counts>
Vec3 VolumeLighting::gather(const Vec3& p, const Vec3& n, bsdf::Rng& rng,
                            const Counts& counts) const {
  Vec3 sum(0.0);
  const int samples = strata_ * strata_;
  for (size_t l = 0; l < samplers_.size(); ++l) {
    const Light& light = scene_.lights()[l];
    if (!(samplers_[l].area() > 0) || light.radiance == Vec3(0.0)) continue;
    // The light emits from its front only: p behind it gets nothing.
    if (!(lightPlanes_[l].signedDistance(p) > 0)) continue;
    double weight = 0;  // Σ accepted cosθp·cosθL/r²
    for (int i = 0; i < strata_; ++i)
      for (int j = 0; j < strata_; ++j) {
        const double ju = rng.uniform(), jv = rng.uniform();
        const Vec3 q = samplers_[l].stratified(i, j, strata_, ju, jv);
        const Vec3 d = q - p;
        const double r2 = glm::dot(d, d);
        const double cosP = glm::dot(n, d), cosL = -glm::dot(lightPlanes_[l].normal, d);
        if (!(cosP > 0 && cosL > 0 && r2 > 0)) continue;
        if (counts(p, q)) weight += cosP * cosL / (r2 * r2);
      }
    sum += light.radiance * (samplers_[l].area() / samples * weight);
  }
  return sum;
}

Vec3 VolumeLighting::volumeIrradiance(uint32_t volume, const Vec3& p, const Vec3& n,
                                      bsdf::Rng& rng) const {
  // Off the surface by a hundredth of a voxel along the normal, so the shadow ray does not
  // find the surface it starts on (the trace's root is ~1e-13 voxel off, Embree's t ~1e-7).
  const Vec3 start = p + 1e-2 * rays_.volumePlacement(volume).voxelSize * n;
  return gather(start, n, rng, [&](const Vec3& from, const Vec3& q) {
    return !rays_.occluded(from, q) && !rays_.volumeOccluded(from, q);
  });
}

Vec3 VolumeLighting::blockedByVolumes(const Vec3& p, const Vec3& n, bsdf::Rng& rng) const {
  if (!rays_.hasVolumes()) return Vec3(0.0);
  return gather(p, n, rng, [&](const Vec3& from, const Vec3& q) {
    return rays_.volumeOccluded(from, q) && !rays_.occluded(from, q);
  });
}

}  // namespace penumbra
