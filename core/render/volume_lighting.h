// Direct light where volumes are involved (README "Volumes"): at an isosurface point, the
// area lights with soft shadows by stratified shadow rays (blocked by polygons and volumes);
// at a polygon point, the light the volumes take away from the DM's exact value. Read-only
// after construction; thread-safe given one Rng per caller.
#pragma once

#include <vector>

#include "core/bsdf/rng.h"
#include "core/raycast/ray_scene.h"
#include "core/render/light_sampler.h"
#include "core/scene/scene.h"

namespace penumbra {

class VolumeLighting {
 public:
  // `strata`: an n×n jittered grid of shadow rays per light and point (n ≥ 1).
  VolumeLighting(const Scene& scene, const RayScene& rays, int strata);

  // Irradiance at point p of volume `volume` with unit normal n (turned towards the viewer):
  // Σ lights radiance · ∫ V · cosθp · cosθL / r², V from polygons (single-sided rule) and
  // every volume's isosurface (its own included: self-shadowing).
  Vec3 volumeIrradiance(uint32_t volume, const Vec3& p, const Vec3& n, bsdf::Rng& rng) const;

  // The part of the irradiance at polygon point p (face normal n) that reaches p past the
  // polygons but is blocked by a volume: E = E_DM − this is the light blocked by neither,
  // the DM's exact value standing for the polygons' part. Zero without volumes.
  Vec3 blockedByVolumes(const Vec3& p, const Vec3& n, bsdf::Rng& rng) const;

 private:
  // Σ over lights and strata of radiance · A/N · cosθp·cosθL/r² for the samples `counts`
  // accepts (called with p and the light point q).
  template <class Counts>
  Vec3 gather(const Vec3& p, const Vec3& n, bsdf::Rng& rng, const Counts& counts) const;

  const Scene& scene_;
  const RayScene& rays_;
  int strata_;
  std::vector<LightSampler> samplers_;
  std::vector<Plane> lightPlanes_;
};

}  // namespace penumbra
