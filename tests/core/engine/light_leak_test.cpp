// No light leaks: wherever one face alone hides a whole light from a point (its
// umbra), and under objects resting on a receiver (contact regions), the DM mesh interpolated
// at that point is dark too. Points are sampled inside the mesh triangles that have
// a shadowed corner, on seeded generated scenes with stacked cubes and tables.
// Umbra made only by several faces together has boundaries the paper's mesh does
// not hold (EEE and non-emitter EV events, §1): those points are counted, not judged.
#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <random>

#include "core/engine/engine.h"
#include "core/raycast/ray_scene.h"
#include "core/reference/exact_irradiance.h"
#include "scenegen/cubes_scene.h"

namespace penumbra {
namespace {

TEST(LightLeak, UmbraPointsAreDarkInTheMesh) {
  size_t checked = 0, umbraPoints = 0, leaks = 0, multiOccluderUmbra = 0, multiOccluderLeaks = 0;
  for (uint64_t seed = 1; seed <= 24; ++seed) {
    CubesSceneOptions options;
    options.cubes = 3 + int(seed % 5);
    options.seed = seed;
    options.lightScale = seed % 2 ? 0.2 : 1.0;
    options.stackedFraction = 0.4;
    options.thinTables = seed % 3 == 0 ? 0.3 : 0.0;
    options.tiltedLight = seed % 4 == 1;
    Engine engine(makeCubesScene(options));
    const Mesh mesh = engine.mesh();
    const ExactReference reference(engine.scene());
    const RayScene rays(engine.scene());
    // Whether p lies under an object resting on its receiver: inside a face lying on
    // the receiver's plane and facing it (a cube's bottom on the floor).
    auto underRestingFace = [&](const Vec3& p, const Vec3& n) {
      for (const Face& face : engine.scene().faces()) {
        if (glm::dot(face.plane.normal, n) > -0.999999) continue;
        if (std::abs(face.plane.signedDistance(p)) > engine.scene().tolerance().onPlane()) continue;
        bool inside = true;
        for (size_t i = 0; i < face.polygon.size() && inside; ++i) {
          const Vec3& a = face.polygon[i];
          const Vec3& b = face.polygon[(i + 1) % face.polygon.size()];
          inside = glm::dot(glm::cross(b - a, p - a), face.plane.normal) > 0;
        }
        if (inside) return true;
      }
      return false;
    };
    // Whether one face blocks every segment from p to the light (its vertices, its
    // centre and seeded points on it): Embree's blockers, independent of the engine.
    auto singleOccluder = [&](const Vec3& p, std::mt19937_64& rng) {
      for (const Light& light : engine.scene().lights()) {
        std::vector<Vec3> targets = light.polygon;
        targets.push_back(centroid(light.polygon));
        std::uniform_real_distribution<double> u(0.0, 1.0);
        for (int k = 0; k < 16; ++k) {
          double a = u(rng), b = u(rng);
          if (a + b > 1) a = 1 - a, b = 1 - b;
          const size_t i = 1 + size_t(u(rng) * double(light.polygon.size() - 2)) % (light.polygon.size() - 2);
          targets.push_back(light.polygon[0] + a * (light.polygon[i] - light.polygon[0]) +
                            b * (light.polygon[i + 1] - light.polygon[0]));
        }
        std::vector<uint32_t> common;
        bool first = true;
        for (const Vec3& q : targets) {
          // Targets behind p's plane or the light's back side carry no light anyway.
          std::vector<uint32_t> blockers = rays.blockers(p, q);
          if (first) common = blockers;
          std::vector<uint32_t> kept;
          std::set_intersection(common.begin(), common.end(), blockers.begin(), blockers.end(),
                                std::back_inserter(kept));
          common = kept;
          first = false;
        }
        if (!common.empty()) return true;
      }
      return false;
    };
    double peak = 0;
    for (const auto& r : mesh.receivers)
      for (const Vec3& e : r.irradiance) peak = std::max(peak, e.x);

    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (const ReceiverMesh& r : mesh.receivers) {
      // Triangles with a dark corner: where umbra and contact edges are.
      std::vector<size_t> dark;
      for (size_t t = 0; t < r.triangles.size(); ++t)
        for (uint32_t i : r.triangles[t])
          if (r.classes[i] != LightClass::Lit) {
            dark.push_back(t);
            break;
          }
      if (dark.empty()) continue;
      for (int k = 0; k < 40; ++k) {
        const auto& t = r.triangles[dark[size_t(uniform(rng) * double(dark.size())) % dark.size()]];
        double a = uniform(rng), b = uniform(rng);
        if (a + b > 1) a = 1 - a, b = 1 - b;
        const Vec3 p = r.positions[t[0]] + a * (r.positions[t[1]] - r.positions[t[0]]) +
                       b * (r.positions[t[2]] - r.positions[t[0]]);
        const Vec3 interpolated = (1 - a - b) * r.irradiance[t[0]] + a * r.irradiance[t[1]] +
                                  b * r.irradiance[t[2]];
        const PointIrradiance truth = reference.evaluate(p, r.normal);
        ++checked;
        if (truth.lightClass != LightClass::Umbra) continue;
        const bool leak = interpolated.x > 1e-12 * peak;
        if (!singleOccluder(p, rng) && !underRestingFace(p, r.normal)) {
          ++multiOccluderUmbra;
          multiOccluderLeaks += leak;
          continue;
        }
        ++umbraPoints;
        if (leak && leaks++ < 5)
          ADD_FAILURE() << "seed " << seed << " face " << r.face.object << "/" << r.face.face
                        << ": light leak " << interpolated.x << " (peak " << peak << ")";
      }
    }
  }
  std::printf("%zu points near shadows; %zu in one face's umbra or under a resting object, %zu leaks; %zu in umbra of several "
              "faces only, %zu of them not dark in the mesh\n",
              checked, umbraPoints, leaks, multiOccluderUmbra, multiOccluderLeaks);
  EXPECT_GT(umbraPoints, 500u);
  EXPECT_EQ(leaks, 0u);
}

}  // namespace
}  // namespace penumbra
