#include "core/render/renderer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>

#include "core/illum/ambient_fill.h"
#include "core/raycast/light_hit.h"
#include "core/raycast/mesh_lookup.h"
#include "core/raycast/ray_scene.h"
#include "core/reference/exact_irradiance.h"
#include "core/render/dm_visibility.h"
#include "core/render/volume_lighting.h"
#include "core/scene/camera_limits.h"
#include "core/util/parallel.h"

namespace penumbra {

namespace {

constexpr double kSurfacePercentile = 0.99;

Vec3 materialAlbedo(const Scene& scene, const std::string& material) {
  if (const auto index = scene.findMaterial(material)) return scene.materials()[*index].albedo;
  return Material{}.albedo;
}

// An isosurface point: its material's albedo (microfacet keys are not used on volumes) over π
// times the shadow-ray irradiance plus the ambient term; the normal turned to the viewer.
Vec3 volumeRadiance(const Scene& scene, const VolumeLighting& lighting, const RayScene::Hit& hit,
                    const Vec3& dir, const Vec3& ambient, bsdf::Rng& rng) {
  const VolumeObject& volume = scene.volumes()[*hit.volume];
  const Vec3 n = glm::dot(hit.volumeNormal, dir) < 0 ? hit.volumeNormal : -hit.volumeNormal;
  const Vec3 irradiance = lighting.volumeIrradiance(*hit.volume, hit.position, n, rng);
  return materialAlbedo(scene, volume.material) / M_PI * (irradiance + ambient);
}

void checkSettings(const RenderSettings& settings) {
  for (const auto& [name, value] : {std::pair{"width", settings.width}, std::pair{"height", settings.height}}) {
    if (value < 1 || value > RenderSettings::kMaxSize)
      throw std::invalid_argument(std::string("render: ") + name + " " + std::to_string(value) +
                                  " is outside 1.." + std::to_string(RenderSettings::kMaxSize));
  }
  if (!(settings.ambientFraction >= 0) || !(settings.exposure >= 0))
    throw std::invalid_argument("render: ambient fraction and exposure must be non-negative");
}

// Counts the surface and light pixels (kind 1, 2), picks the exposure (`exposure`, or 0: one
// over the 99th percentile of the surface pixels' largest channel) and writes the sRGB bytes.
void exposeAndEncode(RenderedImage& image, const std::vector<uint8_t>& kind, double exposure) {
  const size_t pixels = kind.size();
  std::vector<float> surfaceValues;
  for (size_t p = 0; p < pixels; ++p) {
    if (kind[p] == 1) {
      ++image.surfacePixels;
      surfaceValues.push_back(
          std::max({image.linear[3 * p], image.linear[3 * p + 1], image.linear[3 * p + 2]}));
    } else if (kind[p] == 2) {
      ++image.lightPixels;
    }
  }
  image.exposure = exposure;
  if (image.exposure == 0) {
    image.exposure = 1;
    if (!surfaceValues.empty()) {
      const size_t k = std::min(surfaceValues.size() - 1, size_t(kSurfacePercentile * double(surfaceValues.size())));
      std::nth_element(surfaceValues.begin(), surfaceValues.begin() + long(k), surfaceValues.end());
      if (surfaceValues[k] > 0) image.exposure = 1.0 / surfaceValues[k];
    }
  }
  image.srgb.resize(3 * pixels);
  for (size_t k = 0; k < 3 * pixels; ++k)
    image.srgb[k] = uint8_t(std::lround(255 * srgbEncode(image.exposure * image.linear[k])));
}

}  // namespace

double srgbEncode(double linear) {
  const double x = std::clamp(linear, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055;
}

Camera renderCamera(const Scene& scene, const RenderSettings& settings) {
  if (settings.camera) return *settings.camera;
  if (scene.camera()) return *scene.camera();
  return defaultCamera(scene.bounds());
}

RenderedImage render(const Scene& scene, const Mesh& mesh, const RenderSettings& settings,
                     const RenderProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  checkSettings(settings);
  const Camera view = renderCamera(scene, settings);
  validateCamera(view, scene.bounds());  // every path's camera, whoever checked it before
  const CameraProjection camera(view, settings.width, settings.height, settings.convention);

  const RayScene rays(scene);
  const MeshLookup lookup(scene, mesh);
  const ExactReference reference(scene);
  std::vector<bool> receives(scene.faces().size());
  for (size_t i = 0; i < scene.faces().size(); ++i) receives[i] = scene.receivesLight(scene.faces()[i]);
  std::vector<Plane> lightPlanes;
  for (const Light& light : scene.lights()) lightPlanes.push_back(light.plane());

  // Radiance of a diffuse face at a point: albedo/π · (E + ambient); faces receive light on
  // their front only, so a back seen with culling off (or from a glossy path) is ambient.
  // With GI the sensors' indirect irradiance takes the ambient term's place.
  const Vec3 ambient = settings.gi ? Vec3(0.0) : ambientIrradiance(scene, settings.ambientFraction);
  auto diffuseRadiance = [&](uint32_t faceIndex, const Vec3& position, bool frontFacing) {
    const Face& face = scene.faces()[faceIndex];
    Vec3 irradiance(0.0);
    if (receives[faceIndex] && frontFacing) {
      if (settings.reference) {
        irradiance = reference.evaluate(position, face.plane.normal, shadingNormal(face, position)).irradiance;
      } else if (const auto value = lookup.irradiance(faceIndex, position)) {
        irradiance = *value;
      }
    }
    return scene.albedo(face.id) / M_PI * (irradiance + ambient);
  };
  const VisiblePiecesFn fromOccluders =
      settings.occluders && !settings.reference ? backprojectedPieces(scene, settings.occluders) : VisiblePiecesFn{};
  auto visiblePieces = [&](uint32_t faceIndex, const Vec3& p, size_t light, std::vector<Polygon3>& pieces) {
    if (fromOccluders) return fromOccluders(faceIndex, p, light, pieces);
    pieces = reference.visibility(p, scene.faces()[faceIndex].plane.normal, light).visiblePieces;
  };
  const MicrofacetShading microfacet(scene, rays, visiblePieces, diffuseRadiance, settings.microfacet);
  const VolumeLighting volumeLighting(scene, rays, settings.volumeShadowStrata);
  const unsigned cameraMask = rays.hasVolumes() ? kAllRays : kPolygonRays;

  const Parallel parallel(settings.threads);
  // The first front-facing surface and the closest light along the ray of pixel (i, j).
  auto primaryHit = [&](int i, int j, std::optional<size_t>& light) {
    const CameraProjection::Ray ray = camera.rayThrough(Vec2(i + 0.5, j + 0.5));
    // The near→far segment is t in [0, 1].
    const std::optional<RayScene::Hit> surface =
        settings.cullBackFaces ? rays.intersectFront(ray.origin, ray.dir, 0, 1.0, cameraMask)
                               : rays.intersect(ray.origin, ray.dir, 0, 1.0, cameraMask);
    const auto lightHit =
        closestLightHit(scene.lights(), lightPlanes, ray.origin, ray.dir, surface ? surface->t : 1.0);
    light.reset();
    if (lightHit && (!surface || lightHit->t < surface->t)) light = lightHit->light;
    return std::make_pair(ray, light ? std::nullopt : surface);
  };

  RenderedImage image;
  std::vector<Vec3> indirect;  // per pixel, with GI
  if (settings.gi) {
    gi::GBuffer gbuffer{settings.width, settings.height, {}, {}};
    const size_t n = size_t(settings.width) * size_t(settings.height);
    gbuffer.face.assign(n, -1);
    gbuffer.position.assign(n, Vec3(0.0));
    if (rays.hasVolumes()) gbuffer.normal.assign(n, Vec3(0.0));
    parallel.forEach(size_t(settings.height), [&](size_t row) {
      std::optional<size_t> light;
      for (int i = 0; i < settings.width; ++i) {
        const auto [ray, surface] = primaryHit(i, int(row), light);
        const size_t p = row * size_t(settings.width) + size_t(i);
        if (surface && surface->volume) {  // an isosurface: its own id, its normal towards the view
          gbuffer.face[p] = int32_t(scene.faces().size() + *surface->volume);
          gbuffer.position[p] = surface->position;
          const Vec3 n = surface->volumeNormal;
          gbuffer.normal[p] = glm::dot(n, ray.dir) < 0 ? n : -n;
        } else if (surface && surface->frontFacing && !microfacet.isMicrofacet(surface->faceIndex)) {
          gbuffer.face[p] = int32_t(surface->faceIndex);
          gbuffer.position[p] = surface->position;
        }
      }
    });
    auto sensors = [&](size_t placed) { if (progress) progress(placed, 0); };
    image.gi = gi::indirectImage(scene, rays, mesh, gbuffer, *settings.gi, parallel, sensors);
    indirect = std::move(image.gi->irradiance);
    image.gi->irradiance.clear();
  }

  image.width = settings.width;
  image.height = settings.height;
  image.ambientIrradiance = ambient;
  const size_t pixels = size_t(image.width) * size_t(image.height);
  image.linear.assign(3 * pixels, 0.0f);
  // 0: background, 1: surface, 2: light — for the exposure and the counts.
  std::vector<uint8_t> kind(pixels, 0);

  std::atomic<size_t> rowsDone{0};
  std::mutex progressMutex;
  // Rows in parallel; each pixel's value depends only on the pixel (its generator too), so
  // the image is the same on any number of threads (Renderer.OneAndTwoThreadsDrawTheSameBytes).
  parallel.forEach(size_t(image.height), [&](size_t row) {
    const int j = int(row);
    for (int i = 0; i < image.width; ++i) {
      std::optional<size_t> light;
      const auto [ray, surface] = primaryHit(i, j, light);

      Vec3 radiance = settings.background;
      const size_t p = size_t(j) * image.width + i;
      if (light) {
        radiance = scene.lights()[*light].radiance;
        kind[p] = 2;
      } else if (surface && surface->volume) {
        bsdf::Rng rng(settings.seed * 0x9E3779B97F4A7C15ull + p);
        radiance = volumeRadiance(scene, volumeLighting, *surface, ray.dir, ambient, rng);
        if (!indirect.empty())
          radiance += materialAlbedo(scene, scene.volumes()[*surface->volume].material) / M_PI * indirect[p];
        kind[p] = 1;
      } else if (surface && microfacet.isMicrofacet(surface->faceIndex)) {
        bsdf::Rng rng(settings.seed * 0x9E3779B97F4A7C15ull + p);
        radiance = microfacet.radiance(surface->faceIndex, surface->position,
                                       -glm::normalize(ray.dir), rng);
        kind[p] = 1;
      } else if (surface) {
        radiance = diffuseRadiance(surface->faceIndex, surface->position, surface->frontFacing);
        if (rays.hasVolumes() && surface->frontFacing && receives[surface->faceIndex]) {
          // The DM has the polygons' shadows exactly; take off what the volumes block.
          bsdf::Rng rng(settings.seed * 0x9E3779B97F4A7C15ull + p);
          const Vec3 kd = scene.albedo(surface->face) / M_PI;
          const Face& face = scene.faces()[surface->faceIndex];
          const Vec3 blocked = volumeLighting.blockedByVolumes(surface->position, face.plane.normal, rng);
          radiance = glm::max(radiance - kd * blocked, kd * ambient);
        }
        if (!indirect.empty()) radiance += scene.albedo(surface->face) / M_PI * indirect[p];
        kind[p] = 1;
      }
      for (int c = 0; c < 3; ++c) image.linear[3 * p + c] = float(radiance[c]);
    }
    if (progress) {
      const size_t done = ++rowsDone;
      std::lock_guard lock(progressMutex);
      progress(done, size_t(image.height));
    }
  });

  exposeAndEncode(image, kind, settings.exposure);
  image.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return image;
}

}  // namespace penumbra
