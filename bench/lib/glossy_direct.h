// The two direct-light estimators the microfacet bench compares, and the image loop they share:
// at every pixel whose primary ray hits a microfacet face, Σ over lights of ∫ f(wo, wi) L_e
// cosθ cosθ_L / r² dA with stratified uniform points on the light. The DM estimator integrates
// over the exactly visible pieces (MicrofacetShading::direct, no shadow rays); the shadow-ray
// estimator over the whole light with one Embree shadow ray per point. Same BSDF, same frame,
// same stratification. Immutable after construction; thread-safe (one Rng per row).
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "core/raycast/camera_projection.h"
#include "core/raycast/ray_scene.h"
#include "core/render/microfacet_shading.h"

namespace penumbra {

// samples: stratified points per light, rows × columns of them (rows = ⌊√samples⌋): over the whole
// light (shadow rays) or split over its visible pieces by area (DM, at least one per piece).
using DirectFn = std::function<Vec3(uint32_t face, const Vec3& p, const Vec3& toViewer, int samples,
                                    bsdf::Rng& rng)>;

// Direct light by shadow rays to stratified uniform points on each whole light.
class ShadowRayDirect {
 public:
  ShadowRayDirect(const Scene& scene, const RayScene& rays);
  Vec3 operator()(uint32_t face, const Vec3& p, const Vec3& toViewer, int samples,
                  bsdf::Rng& rng) const;
  bool isMicrofacet(uint32_t face) const { return bsdfOfFace_[face] >= 0; }

 private:
  const Scene& scene_;
  const RayScene& rays_;
  std::vector<bsdf::MicrofacetBsdf> bsdfs_;
  std::vector<int> bsdfOfFace_;  // per Scene::faces() index, -1: diffuse
};

// The camera view of a scene: which pixels see a microfacet face, and the loop over them.
class GlossyView {
 public:
  GlossyView(const Scene& scene, const RayScene& rays, const Camera& camera, int width, int height,
             std::function<bool(uint32_t face)> isMicrofacet);
  int width() const { return camera_.width(); }
  int height() const { return camera_.height(); }
  // 1 where the pixel centre's primary ray first hits (the front of) a microfacet face.
  const std::vector<uint8_t>& glossyMask() const { return mask_; }
  size_t glossyPixels() const { return glossyPixels_; }

  struct Run {
    std::vector<float> linear;  // RGB per pixel; microfacet pixels only, others 0
    double seconds = 0;         // wall time: primary rays + the estimator, all pixels
    double cpuSeconds = 0;      // the process's CPU time over the same span
  };
  // Traces every pixel's primary ray again (timed with the estimator) and estimates the
  // microfacet pixels with `samples`; each row's generator is seeded from (seed, row).
  Run render(const DirectFn& estimate, int samples, uint64_t seed, int threads) const;

  // The first front-facing hit along the pixel centre's ray (backs are passed through).
  std::optional<RayScene::Hit> primaryHit(int i, int j) const;

 private:
  const Scene& scene_;
  const RayScene& rays_;
  CameraProjection camera_;
  std::function<bool(uint32_t)> isMicrofacet_;
  std::vector<uint8_t> mask_;
  size_t glossyPixels_ = 0;
};

}  // namespace penumbra
