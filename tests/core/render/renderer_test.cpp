// The renderer on real scenes with real Embree and the real engine: a parallel-plate scene whose
// umbra and lit points are known by construction, the bundled Cornell box (light pixels, a
// projected point hit by its own pixel's ray, DM shading against exact-reference shading), size
// limits, and the mesh lookup's interpolation.
#include "core/render/renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/engine/engine.h"
#include "core/raycast/mesh_lookup.h"
#include "core/raycast/ray_scene.h"
#include "core/reference/exact_irradiance.h"
#include "protocol/scene_json.h"

namespace penumbra {
namespace {

double luminance(const Vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

Object upFacingQuad(const std::string& id, double half, double y) {
  Object object;
  object.id = id;
  // Counter-clockwise seen from above: faces +y.
  object.vertices = {{-half, y, -half}, {-half, y, half}, {half, y, half}, {half, y, -half}};
  object.faces = {{0, 1, 2, 3}};
  return object;
}

// A floor, a plate 1 m above it and a small light 3 m up: the floor at the origin is in the
// plate's umbra (the light's shadow through the plate spans |x|, |z| ≤ 0.8), at z = 2.5 fully lit.
Scene plateScene() {
  Light light;
  light.id = "light";
  light.polygon = {{-0.2, 3, -0.2}, {0.2, 3, -0.2}, {0.2, 3, 0.2}, {-0.2, 3, 0.2}};  // faces −y
  light.radiance = Vec3(10, 8, 6);
  Camera camera;
  camera.position = Vec3(0, 0.4, 5);  // below the plate: sees the floor under it
  camera.target = Vec3(0, 0.2, 0);
  camera.fovYDeg = 60;
  camera.near = 0.05;
  camera.far = 20;
  return Scene({light}, {}, {upFacingQuad("floor", 4, 0), upFacingQuad("plate", 1, 1)}, camera);
}

const Scene& cornell() {
  static const Scene scene = protocol::loadSceneFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell.scene.json");
  return scene;
}

const Mesh& cornellMesh() {
  static const Mesh mesh = [] {
    Engine engine(cornell());
    return engine.mesh();
  }();
  return mesh;
}

TEST(Renderer, UmbraShowsAmbientOnlyAndLitFloorShowsExactIrradiance) {
  const Scene scene = plateScene();
  Engine engine(scene);
  const Mesh mesh = engine.mesh();
  RenderSettings settings;
  settings.width = 96;
  settings.height = 64;
  const RenderedImage image = render(scene, mesh, settings);
  const CameraProjection camera(*scene.camera(), settings.width, settings.height);
  const RayScene rays(scene);
  const ExactReference reference(scene);
  const Vec3 albedo = scene.albedo(scene.faces()[0].id);

  const auto umbra = camera.pixelOf(Vec3(0, 0, 0));
  const auto lit = camera.pixelOf(Vec3(0, 0, 2.5));
  ASSERT_TRUE(umbra && lit);
  // Both pixels' rays hit the floor (face 0), and the reference agrees on the classes.
  for (const auto& [pixel, expected] : {std::pair{*umbra, LightClass::Umbra}, std::pair{*lit, LightClass::Lit}}) {
    const auto ray = camera.rayThrough(Vec2(pixel.i + 0.5, pixel.j + 0.5));
    const auto hit = rays.intersect(ray.origin, ray.dir, 0, 1);
    ASSERT_TRUE(hit);
    ASSERT_EQ(hit->faceIndex, 0u);
    const PointIrradiance exact = reference.evaluate(hit->position, Vec3(0, 1, 0));
    ASSERT_EQ(exact.lightClass, expected);
    const Vec3 expectedRadiance = albedo / M_PI * (exact.irradiance + image.ambientIrradiance);
    const Vec3 got = image.pixel(pixel.i, pixel.j);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(got[c], expectedRadiance[c], 0.01 * expectedRadiance[c] + 1e-6)
          << toString(expected) << " channel " << c;
  }
  const Vec3 umbraRadiance = image.pixel(umbra->i, umbra->j);
  EXPECT_GT(luminance(image.pixel(lit->i, lit->j)), 5 * luminance(umbraRadiance));
  EXPECT_GT(luminance(umbraRadiance), 0) << "ambient keeps umbra visible";
}

TEST(Renderer, CornellLightPixelsAreTheBrightest) {
  RenderSettings settings;
  settings.width = 64;
  settings.height = 48;
  const RenderedImage image = render(cornell(), cornellMesh(), settings);
  ASSERT_EQ(image.linear.size(), 3u * 64 * 48);
  ASSERT_EQ(image.srgb.size(), 3u * 64 * 48);
  EXPECT_GT(image.lightPixels, 0u);
  EXPECT_GT(image.surfacePixels, 64u * 48 / 2);

  const Light& light = cornell().lights()[0];
  const CameraProjection camera(*cornell().camera(), 64, 48);
  const auto centre = camera.pixelOf(centroid(light.polygon));
  ASSERT_TRUE(centre);
  const Vec3 atLight = image.pixel(centre->i, centre->j);
  for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(float(atLight[c]), float(light.radiance[c]));
  const size_t k = 3 * (size_t(centre->j) * 64 + centre->i);
  EXPECT_EQ(image.srgb[k], 255);

  // Every pixel at least as bright as the light is a light pixel (its radiance exactly).
  size_t asBright = 0;
  for (int j = 0; j < 48; ++j)
    for (int i = 0; i < 64; ++i)
      if (luminance(image.pixel(i, j)) >= luminance(light.radiance)) {
        ++asBright;
        EXPECT_EQ(image.pixel(i, j), Vec3(glm::vec3(light.radiance))) << i << ", " << j;
      }
  EXPECT_EQ(asBright, image.lightPixels);
}

TEST(Renderer, AProjectedPointIsHitByTheRayThroughItsPixel) {
  const Scene& scene = cornell();
  const auto block = scene.findObject("short_block");
  ASSERT_TRUE(block);
  const uint32_t handle = scene.handleOf(*block);
  const int width = 320, height = 240;
  const CameraProjection camera(*scene.camera(), width, height);
  const RayScene rays(scene);
  int checked = 0;
  for (uint32_t f = 0; f < scene.faces().size(); ++f) {
    const Face& face = scene.faces()[f];
    if (face.id.object != handle || face.plane.normal.y < 0.9) continue;  // the block's top
    const Vec3 middle = centroid(face.polygon);
    for (const Vec3& corner : face.polygon) {
      const Vec3 p = corner + 0.1 * (middle - corner);  // just inside the corner
      const auto pixel = camera.pixelOf(p);
      ASSERT_TRUE(pixel);
      const auto ray = camera.rayThrough(Vec2(pixel->i + 0.5, pixel->j + 0.5));
      const auto hit = rays.intersect(ray.origin, ray.dir, 0, 1);
      ASSERT_TRUE(hit);
      EXPECT_EQ(hit->faceIndex, f);
      // Within a pixel's footprint on the face (widened by the obliquity of the view).
      const double depth = glm::length(p - camera.rayThrough(Vec2(pixel->i + 0.5, pixel->j + 0.5)).origin);
      const double footprint = 2 * depth * std::tan(glm::radians(scene.camera()->fovYDeg) / 2) / height;
      const double cosine = std::abs(glm::dot(glm::normalize(ray.dir), face.plane.normal));
      EXPECT_LT(glm::length(hit->position - p), std::sqrt(2.0) * footprint / cosine);
      // And the hit projects back onto the pixel centre (Embree's float hit: 1e-3 px).
      const auto back = camera.toPixel(hit->position);
      EXPECT_NEAR(back->x, pixel->i + 0.5, 1e-3);
      EXPECT_NEAR(back->y, pixel->j + 0.5, 1e-3);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 4);
}

// Mean absolute difference over surface pixels relative to their mean (Embree's image-compare
// style: a threshold on the error, not byte equality).
double relativeMeanDifference(const RenderedImage& a, const RenderedImage& b) {
  double difference = 0, sum = 0;
  for (size_t k = 0; k < a.linear.size(); ++k) {
    difference += std::abs(double(a.linear[k]) - double(b.linear[k]));
    sum += std::abs(double(b.linear[k]));
  }
  return difference / sum;
}

TEST(Renderer, MeshShadingMatchesExactReferenceShading) {
  RenderSettings settings;
  settings.width = 64;
  settings.height = 48;
  settings.camera = *cornell().camera();
  // Look at the floor and blocks only (no light pixels to dominate the sums).
  settings.camera->target = Vec3(2.78, 0.6, 2.8);
  const RenderedImage mesh = render(cornell(), cornellMesh(), settings);
  settings.reference = true;
  const RenderedImage exact = render(cornell(), Mesh{}, settings);
  EXPECT_EQ(mesh.lightPixels, 0u);
  EXPECT_EQ(mesh.surfacePixels, exact.surfacePixels);
  // The DM mesh is exact at its vertices and linear between them: a few percent at most.
  const double difference = relativeMeanDifference(mesh, exact);
  EXPECT_LT(difference, 0.02);
  RecordProperty("relative_mean_difference", std::to_string(difference));

  // And the comparison can fail: without the direct term the images differ grossly.
  settings.reference = false;
  const RenderedImage dark = render(cornell(), Mesh{}, settings);
  EXPECT_GT(relativeMeanDifference(dark, exact), 0.5);
}

TEST(Renderer, RefusesSizesOutsideTheLimits) {
  RenderSettings settings;
  for (auto [w, h] : {std::pair{0, 48}, std::pair{64, 0}, std::pair{-3, 10},
                      std::pair{RenderSettings::kMaxSize + 1, 10}, std::pair{10, RenderSettings::kMaxSize + 1}}) {
    settings.width = w;
    settings.height = h;
    EXPECT_THROW(render(cornell(), Mesh{}, settings), std::invalid_argument) << w << "x" << h;
  }
}

TEST(Renderer, BackFacesAreSeenThroughUnlessCullingIsOff) {
  // From below the plate: with culling the floor shows through its back; without, the plate's
  // unlit back fills the pixel.
  const Scene scene = plateScene();
  Engine engine(scene);
  const Mesh mesh = engine.mesh();
  RenderSettings settings;
  settings.width = 32;
  settings.height = 32;
  settings.camera = Camera{};
  settings.camera->position = Vec3(0, 0.5, 0.01);
  settings.camera->target = Vec3(0, 2, 0);
  settings.camera->up = Vec3(0, 0, -1);
  const RenderedImage culled = render(scene, mesh, settings);
  settings.cullBackFaces = false;
  const RenderedImage solid = render(scene, mesh, settings);
  const Vec3 middleCulled = culled.pixel(16, 16), middleSolid = solid.pixel(16, 16);
  // Culled: the light straight above; solid: the plate's back (ambient only).
  EXPECT_EQ(middleCulled, Vec3(glm::vec3(scene.lights()[0].radiance)));
  const Vec3 ambientOnly = scene.albedo(scene.faces()[1].id) / M_PI * solid.ambientIrradiance;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(middleSolid[c], ambientOnly[c], 1e-6);
}

TEST(Renderer, OneAndTwoThreadsDrawTheSameBytes) {
  // Diffuse shading from the mesh (Cornell box) and glossy shading with per-pixel generators
  // (the plate scene on a rough conductor floor).
  const Scene plate = plateScene();
  Material metal{"metal", Vec3(0.8)};
  metal.type = MaterialType::Conductor;
  metal.roughness = Vec2(0.3, 0.15);
  std::vector<Object> objects = plate.objects();
  objects[0].material = "metal";  // the floor
  const Scene glossy(plate.lights(), {metal}, objects, plate.camera());
  const Mesh glossyMesh = Engine(glossy).mesh();

  for (const auto& [scene, mesh] :
       {std::pair{&cornell(), &cornellMesh()}, std::pair{&glossy, &glossyMesh}}) {
    RenderSettings settings;
    settings.width = 40;
    settings.height = 30;
    settings.threads = 1;
    const RenderedImage one = render(*scene, *mesh, settings);
    settings.threads = 2;
    const RenderedImage two = render(*scene, *mesh, settings);
    ASSERT_GT(one.surfacePixels, 40u * 30 / 4);  // not just background
    EXPECT_EQ(one.linear, two.linear);
    EXPECT_EQ(one.srgb, two.srgb);
    EXPECT_EQ(one.exposure, two.exposure);
  }

  // The comparison can fail: the glossy floor's estimates change with the generators' seed.
  RenderSettings settings;
  settings.width = 40;
  settings.height = 30;
  const RenderedImage first = render(glossy, glossyMesh, settings);
  settings.seed = 2;
  EXPECT_NE(first.linear, render(glossy, glossyMesh, settings).linear);
}

TEST(MeshLookup, InterpolatesBarycentricallyAndClampsOutside) {
  const Scene scene = plateScene();
  Mesh mesh;
  ReceiverMesh floor;
  floor.face = scene.faces()[0].id;
  floor.normal = Vec3(0, 1, 0);
  floor.positions = {{-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}};
  floor.irradiance = {Vec3(0), Vec3(1), Vec3(2), Vec3(1)};  // = (x + z)/8 + 1: linear
  floor.classes.assign(4, LightClass::Lit);
  floor.triangles = {{0, 1, 2}, {0, 2, 3}};
  mesh.receivers.push_back(floor);
  const MeshLookup lookup(scene, mesh);
  EXPECT_TRUE(lookup.hasReceiver(0));
  EXPECT_FALSE(lookup.hasReceiver(1));
  EXPECT_FALSE(lookup.irradiance(1, Vec3(0, 1, 0)));
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(1.5, 0, -2.25), Vec3(-3.9, 0, 3.9), Vec3(2, 0, 2)}) {
    const auto value = lookup.irradiance(0, p);
    ASSERT_TRUE(value);
    EXPECT_NEAR(value->x, (p.x + p.z) / 8 + 1, 1e-12) << p.x << ", " << p.z;
  }
  // Just outside the face: the nearest edge point's value.
  EXPECT_NEAR(lookup.irradiance(0, Vec3(4.001, 0, 0))->x, 1.5, 1e-12);
}

}  // namespace
}  // namespace penumbra
