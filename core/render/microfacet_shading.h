// Radiance that microfacet surfaces (rough diffuse, conductor, dielectric) send to the viewer:
// the BSDF integrated over the exactly visible part of each light with stratified samples (no
// shadow rays), plus BSDF-sampled paths through Embree for what the lights do not cover.
// Immutable after construction; radiance() is thread-safe given one Rng per thread.
#pragma once

#include <functional>
#include <vector>

#include "core/bsdf/bsdf.h"
#include "core/geom/polygon.h"
#include "core/raycast/ray_scene.h"
#include "core/scene/scene.h"

namespace penumbra {

struct MicrofacetSettings {
  int lightSamples = 16;  // stratified samples per light, split over its visible pieces by area
  int pathsPerPixel = 16; // sampled paths averaged per microfacet point
  int maxDepth = 4;       // microfacet vertices along a path (the last one gets direct light only)
};

// The visible pieces of light `light` from p on face `faceIndex` (world space, on the light's
// plane); must be exact: the DM's occluder list through a Backprojection, or every face.
using VisiblePiecesFn =
    std::function<void(uint32_t faceIndex, const Vec3& p, size_t light, std::vector<Polygon3>& pieces)>;
// Radiance leaving a diffuse face at p (its DM irradiance), seen from its front or back.
using DiffuseRadianceFn = std::function<Vec3(uint32_t faceIndex, const Vec3& p, bool frontFacing)>;

class MicrofacetShading {
 public:
  MicrofacetShading(const Scene& scene, const RayScene& rays, VisiblePiecesFn visible, DiffuseRadianceFn diffuse,
                    MicrofacetSettings settings = {});

  bool isMicrofacet(uint32_t faceIndex) const { return bsdfIndex_[faceIndex] >= 0; }
  // Radiance leaving p on a microfacet face towards toViewer (unit; either side of the face):
  // direct() with lightSamples, plus the mean of pathsPerPixel sampled paths (whose later
  // microfacet vertices take direct light with lightSamples / 4 samples).
  Vec3 radiance(uint32_t faceIndex, const Vec3& p, const Vec3& toViewer, bsdf::Rng& rng) const;
  // The light-piece integral alone at one vertex: Σ ∫ f(wo, wi) L_e cosθ cosθ_L / r² dA, with
  // `samples` per light split over its visible pieces by area (at least one each), each piece
  // stratified on its own.
  Vec3 direct(uint32_t faceIndex, const Vec3& p, const Vec3& toViewer, int samples, bsdf::Rng& rng) const;
  // One path's radiance beyond the first vertex's direct light.
  Vec3 indirect(uint32_t faceIndex, const Vec3& p, const Vec3& toViewer, bsdf::Rng& rng) const;

 private:
  struct Frame {
    Vec3 t, b, n;
    Vec3 toLocal(const Vec3& w) const { return {glm::dot(w, t), glm::dot(w, b), glm::dot(w, n)}; }
    Vec3 toWorld(const Vec3& w) const { return w.x * t + w.y * b + w.z * n; }
  };
  Frame frameOf(uint32_t faceIndex) const;

  const Scene& scene_;
  const RayScene& rays_;
  VisiblePiecesFn visible_;
  DiffuseRadianceFn diffuse_;
  MicrofacetSettings settings_;
  std::vector<bsdf::MicrofacetBsdf> bsdfs_;  // one per microfacet material
  std::vector<int> bsdfIndex_;               // per Scene::faces() index, -1: diffuse
};

// The walk parameters of a microfacet material (its type must not be Diffuse).
bsdf::WalkParams walkParamsOf(const Material& material);

}  // namespace penumbra
