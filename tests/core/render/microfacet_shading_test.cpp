// Microfacet shading: the light-piece integral against an independent estimate with shadow
// rays over the whole light (same BSDF, single scattering so that eval is exact), in a
// penumbra; and the DM cell's occluder list giving the same visible light as every face.
#include "core/render/microfacet_shading.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/engine/engine.h"
#include "core/illum/backprojection.h"
#include "core/raycast/ray_scene.h"
#include "core/reference/exact_irradiance.h"

namespace penumbra {
namespace {

Object upQuad(const std::string& id, double half, double y, double x = 0) {
  Object object;
  object.id = id;
  object.vertices = {{x - half, y, -half}, {x - half, y, half}, {x + half, y, half}, {x + half, y, -half}};
  object.faces = {{0, 1, 2, 3}};
  return object;
}

// A conductor floor, a plate 1 m up whose edge runs over the origin, a light 3 m up: the
// floor at the origin sees part of the light.
Scene penumbraScene(bool single) {
  Light light;
  light.id = "light";
  light.polygon = {{-0.5, 3, -0.3}, {0.5, 3, -0.3}, {0.5, 3, 0.3}, {-0.5, 3, 0.3}};
  light.radiance = Vec3(10, 8, 6);
  Material metal{"metal", Vec3(0.8)};
  metal.type = MaterialType::Conductor;
  metal.roughness = Vec2(0.3, 0.15);
  metal.eta = Vec3(0.2, 0.4, 1.4);
  metal.k = Vec3(3.6, 2.4, 1.8);
  metal.singleScattering = single;
  Object floor = upQuad("floor", 4, 0);
  floor.material = "metal";
  return Scene({light}, {metal}, {floor, upQuad("plate", 1, 1, -1.0)});
}

uint32_t faceOf(const Scene& scene, const std::string& object) {
  for (uint32_t i = 0; i < scene.faces().size(); ++i)
    if (scene.object(scene.faces()[i].id.object).id == object) return i;
  return 0;
}

TEST(MicrofacetShading, LightPiecesMatchShadowRaysInAPenumbra) {
  const Scene scene = penumbraScene(true);
  const RayScene rays(scene);
  const ExactReference reference(scene);
  MicrofacetSettings settings;
  settings.lightSamples = 4096;
  const MicrofacetShading shading(
      scene, rays,
      [&](uint32_t f, const Vec3& p, size_t l, std::vector<Polygon3>& pieces) {
        pieces = reference.visibility(p, scene.faces()[f].plane.normal, l).visiblePieces;
      },
      [](uint32_t, const Vec3&, bool) { return Vec3(0.0); }, settings);
  const uint32_t floor = faceOf(scene, "floor");
  const Vec3 p(0.05, 0, 0.1), toViewer = glm::normalize(Vec3(0.3, 1.0, -0.8));
  bsdf::Rng rng(5);
  const double pieces = shading.direct(floor, p, toViewer, settings.lightSamples, rng).x;
  ASSERT_EQ(reference.visibility(p, Vec3(0, 1, 0), 0).lightClass, LightClass::Penumbra);

  // Independent: uniform points on the whole light, a shadow ray each, the same BSDF.
  const bsdf::MicrofacetBsdf bsdf(walkParamsOf(scene.materials()[0]));
  const Light& light = scene.lights()[0];
  const Vec3 t = glm::normalize(scene.faces()[floor].polygon[1] - scene.faces()[floor].polygon[0]);
  const Vec3 n(0, 1, 0), b = glm::cross(n, t);
  auto local = [&](const Vec3& w) { return Vec3(glm::dot(w, t), glm::dot(w, b), glm::dot(w, n)); };
  const int samples = 400000;
  double sum = 0, sum2 = 0;
  int blocked = 0;
  for (int i = 0; i < samples; ++i) {
    const Vec3 q = light.polygon[0] + rng.uniform() * (light.polygon[1] - light.polygon[0]) +
                   rng.uniform() * (light.polygon[3] - light.polygon[0]);
    double v = 0;
    if (rays.occluded(p, q)) {
      ++blocked;
    } else {
      const Vec3 d = q - p;
      const double r2 = glm::dot(d, d);
      const Vec3 wi = d / std::sqrt(r2);
      v = bsdf.eval(local(toViewer), local(wi), rng).x * wi.y * wi.y / r2 * light.area() * light.radiance.x;
    }
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / samples, sigma = std::sqrt((sum2 / samples - mean * mean) / samples);
  EXPECT_GT(blocked, samples / 10);
  EXPECT_LT(blocked, samples * 9 / 10);
  EXPECT_NEAR(pieces, mean, 4 * sigma + 2e-3 * mean) << "sigma " << sigma;
  EXPECT_LT(sigma, 0.01 * mean);
}

// The light's budget is split over its pieces by area (at least one sample each): a small
// budget averaged over many generators equals a large one, where the plate cuts the light.
TEST(MicrofacetShading, SmallBudgetsOverPiecesStayUnbiased) {
  const Scene scene = penumbraScene(true);
  const RayScene rays(scene);
  const ExactReference reference(scene);
  // Two pieces from the one visible polygon: a budget of 2 gives each piece its own samples.
  const MicrofacetShading shading(
      scene, rays,
      [&](uint32_t f, const Vec3& p, size_t l, std::vector<Polygon3>& pieces) {
        for (const Polygon3& piece :
             reference.visibility(p, scene.faces()[f].plane.normal, l).visiblePieces) {
          pieces.push_back({piece[0], piece[1], piece[2]});
          for (size_t k = 3; k < piece.size(); ++k)
            pieces.push_back({piece[0], piece[k - 1], piece[k]});
        }
      },
      [](uint32_t, const Vec3&, bool) { return Vec3(0.0); });
  const uint32_t floor = faceOf(scene, "floor");
  const Vec3 p(0.05, 0, 0.1), toViewer = glm::normalize(Vec3(0.3, 1.0, -0.8));
  bsdf::Rng rng(11);
  const double exact = shading.direct(floor, p, toViewer, 1 << 16, rng).x;
  for (int budget : {1, 2, 5}) {
    const int runs = 20000;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < runs; ++i) {
      const double v = shading.direct(floor, p, toViewer, budget, rng).x;
      sum += v;
      sum2 += v * v;
    }
    const double mean = sum / runs, sigma = std::sqrt((sum2 / runs - mean * mean) / runs);
    EXPECT_NEAR(mean, exact, 4 * sigma + 1e-3 * exact)
        << "budget " << budget << ", sigma " << sigma;
  }
}

TEST(MicrofacetShading, DmOccluderListsGiveTheExactVisibleLight) {
  const Scene scene = penumbraScene(false);
  Engine engine(scene);
  const ExactReference reference(scene);
  const uint32_t floor = faceOf(scene, "floor");
  const Engine::Receiver* receiver = engine.receiver(scene.faces()[floor].id);
  ASSERT_NE(receiver, nullptr);
  bsdf::Rng rng(9);
  int penumbra = 0;
  for (int i = 0; i < 400; ++i) {
    const Vec3 p(-2 + 4 * rng.uniform(), 0, -2 + 4 * rng.uniform());
    Backprojection dm(scene, 0, p, Vec3(0, 1, 0));
    for (const OccluderEntry& e : receiver->tree.occluders(receiver->tree.locate(receiver->frame.to2D(p))))
      if (e.light == 0 && e.face != kLightPlaneOccluder)
        for (const Face& f : scene.faces())
          if (f.id == e.face) dm.occlude(f);
    const LightVisibility exact = reference.visibility(p, Vec3(0, 1, 0), 0);
    double dmFactor = 0, exactFactor = 0;
    for (const Polygon3& piece : dm.visiblePieces()) dmFactor += lambertFactor(p, Vec3(0, 1, 0), piece);
    for (const Polygon3& piece : exact.visiblePieces) exactFactor += lambertFactor(p, Vec3(0, 1, 0), piece);
    EXPECT_NEAR(dmFactor, exactFactor, 1e-9 * (1 + exactFactor)) << p.x << " " << p.z;
    penumbra += exact.lightClass == LightClass::Penumbra;
  }
  EXPECT_GT(penumbra, 10);
}

}  // namespace
}  // namespace penumbra
