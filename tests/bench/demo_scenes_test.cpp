// The hand-made scenes shipped in scenes/: they load, their geometry is sound, and
// the exact reference and the Monte Carlo estimator agree on them.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "core/reference/exact_irradiance.h"
#include "core/reference/monte_carlo.h"
#include "protocol/scene_json.h"

namespace penumbra {
namespace {

Scene load(const std::string& name) {
  return protocol::loadSceneFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + name);
}

// Signed volume by the divergence theorem: positive iff faces point outwards.
double signedVolume(const Scene& scene, size_t object) {
  double volume = 0;
  for (const Face& face : scene.faces())
    if (face.id.object == object)
      volume += face.area * glm::dot(face.plane.normal, centroid(face.polygon)) / 3;
  return volume;
}

struct Expectation {
  std::string file;
  std::vector<std::string> roomSurfaces;  // single quads facing into the room
  std::vector<std::string> solids;        // closed objects (boxes)
};

class DemoScene : public ::testing::TestWithParam<Expectation> {};

TEST_P(DemoScene, GeometryIsSound) {
  const Expectation& expect = GetParam();
  const Scene scene = load(expect.file);
  ASSERT_TRUE(scene.camera());
  ASSERT_EQ(scene.objects().size(), expect.roomSurfaces.size() + expect.solids.size());
  const Bounds bounds = scene.bounds();
  const Vec3 centre = bounds.center();
  const double eps = scene.tolerance().length();

  for (const Face& face : scene.faces()) {
    EXPECT_LE(planarityError(face.polygon), kRelativePlanarity);
    EXPECT_TRUE(isConvex(face.polygon));
  }
  for (const std::string& id : expect.roomSurfaces) {
    const auto o = scene.findObject(id);
    ASSERT_TRUE(o) << id;
    for (const Face& face : scene.faces())
      if (face.id.object == *o) {
        EXPECT_GT(face.plane.signedDistance(centre), 0) << id;
      }
  }
  double highest = 0;
  for (const std::string& id : expect.solids) {
    const auto o = scene.findObject(id);
    ASSERT_TRUE(o) << id;
    EXPECT_GT(signedVolume(scene, *o), 0) << id;
    for (const Face& face : scene.faces())
      if (face.id.object == *o)
        for (const Vec3& v : face.polygon) {
          highest = std::max(highest, v.y);
          EXPECT_GE(v.y, -eps) << id;  // nothing below the floor
        }
  }
  for (const Light& light : scene.lights()) {
    EXPECT_TRUE(isConvex(light.polygon));
    EXPECT_LT(light.plane().normal.y, -0.5);  // shines down into the room
    for (const Vec3& v : light.polygon) {
      EXPECT_LT(v.y, bounds.max.y);  // below the ceiling
      EXPECT_GT(v.y, highest);       // above the furniture
      EXPECT_GT(v.x, bounds.min.x);
      EXPECT_LT(v.x, bounds.max.x);
      EXPECT_GT(v.z, bounds.min.z);
      EXPECT_LT(v.z, bounds.max.z);
    }
  }
}

TEST_P(DemoScene, ReferenceAndMonteCarloAgree) {
  const Scene scene = load(GetParam().file);
  const ExactReference reference(scene);
  const MonteCarloEstimator mc(scene);
  std::vector<const Face*> receivers;
  for (const Face& face : scene.faces())
    if (scene.receivesLight(face)) receivers.push_back(&face);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Vec3> points, normals;
  for (int i = 0; i < 150; ++i) {
    const Face& face = *receivers[std::uniform_int_distribution<size_t>(0, receivers.size() - 1)(rng)];
    // A random point of the face: a random convex combination of its corners.
    Vec3 p{0.0};
    double total = 0;
    for (const Vec3& v : face.polygon) {
      const double w = -std::log(1 - unit(rng));
      p += w * v;
      total += w;
    }
    points.push_back(p / total);
    normals.push_back(face.plane.normal);
  }
  MonteCarloOptions options;
  options.samplesPerLight = 4096;
  options.stratified = true;
  const auto estimates = mc.estimateMany(points, normals, options);
  std::vector<PointIrradiance> exact;
  double peak = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    exact.push_back(reference.evaluate(points[i], normals[i]));
    peak = std::max(peak, exact.back().irradiance.x);
  }
  EXPECT_GT(peak, 0);
  size_t within4 = 0, penumbra = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    bool ok4 = true;
    for (int c = 0; c < 3; ++c) {
      const double diff = std::abs(exact[i].irradiance[c] - estimates[i].irradiance[c]);
      const double se = estimates[i].standardError[c];
      ok4 &= diff <= 4 * se + 1e-12 * peak;
      EXPECT_LE(diff, 6 * se + 1e-12 * peak) << "point " << i;
    }
    within4 += ok4;
    penumbra += exact[i].lightClass == LightClass::Penumbra;
  }
  EXPECT_GE(within4 + 1, points.size());  // at most one point beyond 4 se
  EXPECT_GT(penumbra, 0u);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, DemoScene,
    ::testing::Values(
        Expectation{"cornell.scene.json",
                    {"floor", "ceiling", "back_wall", "red_wall", "green_wall"},
                    {"short_block", "tall_block"}},
        Expectation{"office.scene.json",
                    {"floor", "ceiling", "wall_n", "wall_s", "wall_e", "wall_w"},
                    {"table", "chair_1", "chair_2", "chair_3", "cabinet"}}),
    [](const auto& info) { return info.param.file.substr(0, info.param.file.find('.')); });

}  // namespace
}  // namespace penumbra
