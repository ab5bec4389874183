// Images of a lit scene: Embree primary rays through each pixel centre (the exact inverse of the
// camera's view-projection), surfaces shaded from the DM mesh (or the exact reference), lights
// drawn as their radiance; linear float RGB plus a tone-mapped 8-bit sRGB copy. Thread-safe.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "core/gi/sensor_gi.h"
#include "core/illum/ambient_fill.h"
#include "core/mesh/mesh.h"
#include "core/raycast/camera_projection.h"
#include "core/render/microfacet_shading.h"
#include "core/scene/scene.h"

namespace penumbra {

struct RenderSettings {
  static constexpr int kMaxSize = 8192;  // per side; larger requests are refused
  int width = 512;
  int height = 512;
  // The view; empty: the scene's camera, else defaultCamera(scene bounds).
  std::optional<Camera> camera;
  ClipConvention convention;  // any convention draws the same image; kept for tests
  // Shade each hit with ExactReference::evaluate instead of the mesh (slow; for comparison).
  bool reference = false;
  // Faces are single-sided: rays pass through a face seen from behind (three.js FrontSide),
  // so a room can be looked into from outside. Without culling a back shows the ambient part only.
  bool cullBackFaces = true;
  // Ambient irradiance (W·m⁻², per channel) = ambientFraction × the lights' total emitted
  // power (Σ π·radiance·area) / the surface area of the scene's bounding box — roughly that
  // fraction of the mean irradiance if all power landed evenly on the box. Radiance of a
  // surface = albedo/π · (E + ambient); faces that receive no light get the ambient part only.
  double ambientFraction = kDefaultAmbientFraction;
  Vec3 background{0.0};  // radiance of rays that hit nothing
  // Linear scale before tone mapping; 0 = automatic (see RenderedImage::exposure).
  double exposure = 0;
  // Microfacet materials (README "Materials"): light-piece samples and path depth.
  MicrofacetSettings microfacet;
  // The faces that can hide light `light` from p on receiving face `face` (appended to out):
  // the DM cell's occluder list (Engine::Receiver::tree). Empty: every face of the scene.
  // Either way the visible light pieces are exact (Backprojection).
  std::function<void(FaceId face, const Vec3& p, size_t light, std::vector<FaceId>& out)> occluders;
  // Bounced light by sensors (README "Global illumination", core/gi/): replaces the ambient
  // term with the indirect irradiance at each visible point. Empty: direct light + ambient.
  std::optional<gi::GiSettings> gi;
  // Volume objects (README "Volumes"): an n×n jittered grid of shadow rays per light at each
  // isosurface point (soft shadows, blocked by polygons and volumes) and at each diffuse
  // polygon point (the light the volumes block, taken off the DM value). n² rays per light.
  int volumeShadowStrata = 4;
  uint64_t seed = 1;  // microfacet and volume estimates: per-pixel generators seeded from it
  // Threads drawing rows: 0 = every core, 1 = the calling thread only (EngineSettings::threads;
  // a TSan build always uses 1, core/util/parallel.h). The image is the same for any count.
  int threads = 0;
};

struct RenderedImage {
  int width = 0, height = 0;
  // RGB radiance (W·m⁻²·sr⁻¹), row-major, row 0 at the top: 3·width·height floats.
  std::vector<float> linear;
  // The 8-bit sRGB version: exposure·linear clamped to [0, 1] per channel, then the sRGB
  // transfer function (IEC 61966-2-1), rounded. Same layout as `linear`.
  std::vector<uint8_t> srgb;
  // Automatic exposure: 1 / the 99th percentile of the surface pixels' largest channel (light
  // and background pixels excluded), so lit surfaces span the range and lights clip to white.
  double exposure = 1;
  Vec3 ambientIrradiance{0.0};
  size_t surfacePixels = 0, lightPixels = 0;
  double seconds = 0;  // wall time of render()
  // With RenderSettings::gi: sensors placed, seconds, bounce convergence (the irradiance
  // buffer is dropped).
  std::optional<gi::IndirectImage> gi;

  Vec3 pixel(int i, int j) const {
    const size_t k = 3 * (size_t(j) * size_t(width) + size_t(i));
    return Vec3(linear[k], linear[k + 1], linear[k + 2]);
  }
};

// Called as rows complete (rows done, total rows), from one thread at a time; with GI first as
// sensors are placed (sensors so far, 0).
using RenderProgress = std::function<void(size_t done, size_t total)>;

// Throws std::invalid_argument if width or height is outside 1..kMaxSize, CameraError if
// the camera breaks CameraLimits (core/scene/camera_limits.h) or is degenerate; RayTracingError
// on an Embree failure. `mesh` must belong to `scene` (Engine::mesh()); it is not used with
// settings.reference.
RenderedImage render(const Scene& scene, const Mesh& mesh, const RenderSettings& settings,
                     const RenderProgress& progress = {});

// The camera render() uses for these settings.
Camera renderCamera(const Scene& scene, const RenderSettings& settings);

// The sRGB transfer function of a linear value in [0, 1].
double srgbEncode(double linear);

}  // namespace penumbra
