#include "bench/lib/sample_points.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace penumbra {

std::vector<SurfacePoint> sampleReceivingPoints(const Scene& scene, size_t count, uint64_t seed) {
  // Fan triangles of every receiving face, picked in proportion to their area.
  struct Triangle {
    const Face* face;
    Vec3 a, b, c;
  };
  std::vector<Triangle> triangles;
  std::vector<double> cumulative;
  double total = 0;
  for (const Face& face : scene.faces()) {
    if (!scene.receivesLight(face)) continue;
    for (size_t k = 1; k + 1 < face.polygon.size(); ++k) {
      const Triangle t{&face, face.polygon[0], face.polygon[k], face.polygon[k + 1]};
      total += 0.5 * glm::length(glm::cross(t.b - t.a, t.c - t.a));
      triangles.push_back(t);
      cumulative.push_back(total);
    }
  }
  std::vector<SurfacePoint> points;
  if (triangles.empty()) return points;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  points.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    const double pick = uniform(rng) * total;
    const size_t k = std::min<size_t>(
        std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin(),
        triangles.size() - 1);
    const Triangle& t = triangles[k];
    const double r1 = std::sqrt(uniform(rng)), r2 = uniform(rng);
    points.push_back(SurfacePoint{t.face->id, (1 - r1) * t.a + r1 * (1 - r2) * t.b + r1 * r2 * t.c,
                                  t.face->plane.normal});
  }
  return points;
}

}  // namespace penumbra
