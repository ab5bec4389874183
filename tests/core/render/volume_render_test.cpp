// Volume objects in the renderer: the isosurface as an Embree user geometry in the polygons'
// BVH (hits on the sphere field within the trilinear bound, under a rotated, non-uniformly
// scaled transform too), its silhouette in an image, its soft shadow on the floor (darker than
// the DM value, which has no volume occluders; unchanged away from it), its own lighting
// against the exact unoccluded irradiance, and one or two threads drawing the same bytes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/engine/engine.h"
#include "core/raycast/ray_scene.h"
#include "core/reference/exact_irradiance.h"
#include "core/render/renderer.h"
#include "core/render/volume_lighting.h"
#include "protocol/mesh_json.h"
#include "scenegen/volume_fields.h"

namespace penumbra {
namespace {

constexpr int kSide = 24;  // voxels a side: spacing 1/23 m, the sphere's radius 0.35 m

Object floorQuad() {
  Object floor;
  floor.id = "floor";
  floor.vertices = {{-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, {3, 0, -3}};  // faces +y
  floor.faces = {{0, 1, 2, 3}};
  return floor;
}

Light ceilingLight() {
  Light light;
  light.id = "lamp";
  light.polygon = {
      {-0.25, 3, -0.25}, {0.25, 3, -0.25}, {0.25, 3, 0.25}, {-0.25, 3, 0.25}};  // faces −y
  light.radiance = Vec3(10.0);
  return light;
}

std::shared_ptr<const volume::ScalarVolume> sphereData() {
  static const auto data = [] {
    VolumeFieldSpec spec;
    spec.field = VolumeField::Sphere;
    spec.size = glm::ivec3(kSide);
    return std::make_shared<const volume::ScalarVolume>(makeVolumeField(spec),
                                                        Mat3(1.0 / (kSide - 1)));
  }();
  return data;
}

// The unit-cube volume placed so the sphere's centre is at (0, 1.5, 0) (with the default
// transform), radius 0.35 m.
VolumeObject sphereVolume(Transform transform = {}) {
  VolumeObject volume;
  volume.id = "blob";
  volume.isovalue = 0.5;  // the sphere field's level set (scenegen/volume_fields.h)
  volume.data = sphereData();
  if (transform == Transform{}) transform.translate = Vec3(-0.5, 1.0, -0.5);
  volume.transform = transform;
  return volume;
}

Scene roomScene(bool withVolume, std::optional<Camera> camera = std::nullopt,
                Transform transform = {}) {
  std::vector<VolumeObject> volumes;
  if (withVolume) volumes.push_back(sphereVolume(transform));
  return Scene({ceilingLight()}, {}, {floorQuad()}, camera, std::move(volumes));
}

// |r − R| in voxels allowed for the sphere field's trilinear interpolant (tests/core/volume:
// 3/(8 r_min), r_min = R − √3), plus float slack for Embree's t.
double sphereBound() {
  const SphereGeometry sphere = sphereGeometry(glm::ivec3(kSide));
  return 3.0 / (8.0 * (sphere.radius - std::sqrt(3.0))) + 1e-3;
}

void expectHitsOnSphere(const Transform& transform, uint64_t seed) {
  const Scene scene = roomScene(true, std::nullopt, transform);
  const RayScene rays(scene);
  const SphereGeometry sphere = sphereGeometry(glm::ivec3(kSide));
  const Mat4 worldFromVoxel = scene.volumes()[0].worldFromVoxel();
  const Mat4 voxelFromWorld = glm::inverse(worldFromVoxel);
  const Vec3 centre = Vec3(worldFromVoxel * glm::dvec4(sphere.centre, 1));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss;
  int hits = 0, misses = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 away = glm::normalize(Vec3(gauss(rng), gauss(rng), gauss(rng)));
    const Vec3 origin = centre + 4.0 * away;
    // Aim at a voxel-space point inside 0.9 R or outside 1.1 R of the centre.
    const bool inside = k % 2 == 0;
    const Vec3 offset = glm::normalize(Vec3(gauss(rng), gauss(rng), gauss(rng))) *
                        (inside ? 0.9 * std::uniform_real_distribution<double>(0, 1)(rng) : 1.1) *
                        sphere.radius;
    const Vec3 aim = Vec3(worldFromVoxel * glm::dvec4(sphere.centre + offset, 1));
    const auto hit = rays.intersect(origin, aim - origin, 0, INFINITY, kVolumeRays);
    if (!inside) {
      // Outside 1.1 R along the aim point: the ray may still graze the sphere further on.
      if (!hit) ++misses;
      continue;
    }
    ASSERT_TRUE(hit && hit->volume) << "ray " << k << " missed the sphere";
    ++hits;
    const Vec3 voxel = Vec3(voxelFromWorld * glm::dvec4(hit->position, 1));
    EXPECT_NEAR(glm::length(voxel - sphere.centre), sphere.radius, sphereBound()) << "ray " << k;
    // The normal is the world-space gradient direction: along voxel-space radial, mapped.
    // The gradient points to larger values: inwards for the sphere field, under any transform.
    EXPECT_LT(glm::dot(hit->volumeNormal, hit->position - centre), 0.0) << "ray " << k;
  }
  EXPECT_EQ(hits, 1000);
  EXPECT_GT(misses, 100);
}

TEST(VolumeRender, HitsLieOnTheSphereFieldWithinTheTrilinearBound) { expectHitsOnSphere({}, 1); }

TEST(VolumeRender, HitsFollowARotatedNonUniformlyScaledTransform) {
  Transform transform;
  transform.translate = Vec3(0.3, 1.1, -0.2);
  transform.rotateDeg = Vec3(20, 35, -10);
  transform.scale = Vec3(1.5, 0.5, 2.0);
  expectHitsOnSphere(transform, 2);
}

TEST(VolumeRender, PolygonQueriesDoNotSeeTheVolume) {
  const Scene scene = roomScene(true);
  const RayScene rays(scene);
  // Straight down through the sphere onto the floor: polygons only hit the floor.
  const auto polygon = rays.intersect(Vec3(0, 2.9, 0), Vec3(0, -1, 0));
  ASSERT_TRUE(polygon);
  EXPECT_FALSE(polygon->volume);
  EXPECT_NEAR(polygon->t, 2.9, 1e-5);
  const auto all = rays.intersect(Vec3(0, 2.9, 0), Vec3(0, -1, 0), 0, INFINITY, kAllRays);
  ASSERT_TRUE(all && all->volume);
  EXPECT_NEAR(all->t, 2.9 - 1.85, sphereBound() / (kSide - 1));  // the sphere's top, y = 1.85
  EXPECT_FALSE(rays.occluded(Vec3(0, 0, 0), Vec3(0, 3, 0)));
  EXPECT_TRUE(rays.volumeOccluded(Vec3(0, 0, 0), Vec3(0, 3, 0)));
  EXPECT_FALSE(rays.volumeOccluded(Vec3(2, 0, 0), Vec3(2, 3, 0)));
}

Camera sideCamera() {
  Camera camera;
  camera.position = Vec3(0, 1.5, 5);
  camera.target = Vec3(0, 1.5, 0);
  camera.projection = Camera::Projection::Orthographic;
  camera.height = 1.6;
  return camera;
}

TEST(VolumeRender, TheSilhouetteIsTheSphere) {
  const Scene scene = roomScene(true, sideCamera());
  Engine engine(scene);
  RenderSettings settings;
  settings.width = 80;
  settings.height = 80;
  const RenderedImage image = render(scene, engine.mesh(), settings);
  // Orthographic, 1.6 m square: pixel (i, j) looks along −z through x, y below.
  const double pixel = 1.6 / 80, radius = 0.35, margin = 2.0 / (kSide - 1) + pixel;
  int inside = 0, outside = 0;
  for (int j = 0; j < 80; ++j)
    for (int i = 0; i < 80; ++i) {
      const double x = -0.8 + (i + 0.5) * pixel, y = 2.3 - (j + 0.5) * pixel;
      const double r = std::hypot(x, y - 1.5);
      const Vec3 value = image.pixel(i, j);
      if (r < radius - margin) {
        ++inside;
        EXPECT_GT(value.x, 0.0) << i << "," << j;
      } else if (r > radius + margin) {
        ++outside;
        EXPECT_EQ(value, Vec3(0.0)) << i << "," << j;
      }
    }
  EXPECT_GT(inside, 400);  // π (0.35 − margin)² / pixel² ≈ 460
  EXPECT_GT(outside, 3000);
  // Lit from above: the top of the sphere is brighter than its bottom (its own shadow).
  EXPECT_GT(image.pixel(40, 40 - 14).x, 3 * image.pixel(40, 40 + 14).x);
}

Camera lowCamera() {
  Camera camera;
  camera.position = Vec3(0, 0.4, 4);  // under the sphere: sees the floor below it
  camera.target = Vec3(0, 0.1, 0);
  camera.fovYDeg = 50;
  return camera;
}

TEST(VolumeRender, TheVolumeShadowsTheFloorBelowTheDmValue) {
  RenderSettings settings;
  settings.width = 96;
  settings.height = 72;
  const Scene plain = roomScene(false, lowCamera()), withVolume = roomScene(true, lowCamera());
  Engine plainEngine(plain), volumeEngine(withVolume);
  settings.exposure = 1;  // the same scale for both
  const RenderedImage without = render(plain, plainEngine.mesh(), settings);
  const RenderedImage with = render(withVolume, volumeEngine.mesh(), settings);
  const CameraProjection projection(lowCamera(), settings.width, settings.height);
  const auto under = projection.pixelOf(Vec3(0, 0, 0));
  const auto aside = projection.pixelOf(Vec3(1.0, 0, 1.5));
  ASSERT_TRUE(under && aside);
  // The DM mesh has no volume occluders: the same with or without the volume...
  EXPECT_EQ(protocol::meshToJson(withVolume, volumeEngine.mesh(), "s"),
            protocol::meshToJson(plain, plainEngine.mesh(), "s"));
  // ...but the image takes the volume's umbra off: only the ambient part is left there.
  const Vec3 dm = without.pixel(under->i, under->j), shadowed = with.pixel(under->i, under->j);
  const Vec3 ambientOnly = Vec3(0.8) / M_PI * with.ambientIrradiance;
  EXPECT_LT(shadowed.x, 0.2 * dm.x);
  EXPECT_NEAR(shadowed.x, ambientOnly.x, 1e-9);
  // Far from the shadow no sample is blocked: the pixel is the DM value exactly.
  EXPECT_EQ(with.pixel(aside->i, aside->j), without.pixel(aside->i, aside->j));
}

TEST(VolumeRender, IsosurfaceLightMatchesTheExactUnoccludedIrradiance) {
  const Scene scene = roomScene(true);
  const RayScene rays(scene);
  const VolumeLighting lighting(scene, rays, 16);
  const Scene plain({ceilingLight()}, {}, {floorQuad()});  // ExactReference keeps a reference
  const ExactReference exact(plain);
  bsdf::Rng rng(7);
  // The top of the sphere, facing the light: nothing between (self-shadow-free).
  const auto top = rays.intersect(Vec3(0.05, 2.9, 0.02), Vec3(0, -1, 0), 0, INFINITY, kVolumeRays);
  ASSERT_TRUE(top && top->volume);
  const Vec3 estimate = lighting.volumeIrradiance(0, top->position, top->volumeNormal, rng);
  const Vec3 reference = exact.evaluate(top->position, top->volumeNormal).irradiance;
  EXPECT_NEAR(estimate.x, reference.x, 0.01 * reference.x);
  // The bottom, facing away from the light, gets nothing; a point under the sphere on the
  // floor has all of its light blocked by the volume.
  const auto bottom =
      rays.intersect(Vec3(0.05, 0.1, 0.02), Vec3(0, 1, 0), 0, INFINITY, kVolumeRays);
  ASSERT_TRUE(bottom && bottom->volume);
  // Turned towards the viewer below (the renderer's rule): it points down, away from the light.
  const Vec3 n = glm::dot(bottom->volumeNormal, Vec3(0, 1, 0)) < 0 ? bottom->volumeNormal
                                                                   : -bottom->volumeNormal;
  EXPECT_LT(n.y, 0.0);
  EXPECT_EQ(lighting.volumeIrradiance(0, bottom->position, n, rng), Vec3(0.0));
  const Vec3 floorExact = exact.evaluate(Vec3(0, 0, 0), Vec3(0, 1, 0)).irradiance;
  EXPECT_NEAR(lighting.blockedByVolumes(Vec3(0, 0, 0), Vec3(0, 1, 0), rng).x, floorExact.x,
              1e-3 * floorExact.x);  // all 256 samples blocked: quadrature error only
}

TEST(VolumeRender, OneAndTwoThreadsDrawTheSameBytes) {
  const Scene scene = roomScene(true, lowCamera());
  Engine engine(scene);
  RenderSettings settings;
  settings.width = 64;
  settings.height = 48;
  settings.threads = 1;
  const RenderedImage one = render(scene, engine.mesh(), settings);
  settings.threads = 2;
  const RenderedImage two = render(scene, engine.mesh(), settings);
  EXPECT_EQ(one.linear, two.linear);
  EXPECT_GT(one.surfacePixels, 0u);
}

}  // namespace
}  // namespace penumbra
