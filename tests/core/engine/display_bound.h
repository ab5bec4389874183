// Test helpers for the display mesh: its error at seeded random receiving points against the
// exact reference (ExactReference, no code shared with the engine), relative to the tolerance,
// and a kept mesh compared with the same engine's mesh made afresh. Header-only; test use.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "bench/lib/sample_points.h"
#include "core/engine/engine.h"
#include "core/raycast/mesh_lookup.h"
#include "core/reference/exact_irradiance.h"

namespace penumbra::testing {

constexpr size_t kBoundPoints = 400;

struct BoundCheck {
  size_t points = 0, over = 0;
  double worst = 0;  // the largest error / (tolerance · local level)
  std::string first;
};

// Each point's error against tolerance × (Σ lights radiance · unshadowed factor), per channel;
// `slack` × that is allowed (the tolerance holds at the refinement's test points, and
// interpolation between them may exceed it by the curvature left).
inline BoundCheck checkBound(const Engine& engine, const Mesh& mesh, double tolerance, double slack,
                             const std::vector<SurfacePoint>& points) {
  const Scene& scene = engine.scene();
  const MeshLookup lookup(scene, mesh);
  const ExactReference reference(scene);
  std::map<FaceId, uint32_t> faceIndex;
  for (uint32_t i = 0; i < scene.faces().size(); ++i) faceIndex[scene.faces()[i].id] = i;
  BoundCheck out;
  for (const SurfacePoint& point : points) {
    const Vec3 exact = reference.evaluate(point.position, point.normal).irradiance;
    const Vec3 interpolated = lookup.irradiance(faceIndex.at(point.face), point.position).value_or(Vec3(0.0));
    Vec3 level(0.0);
    for (size_t l = 0; l < scene.lights().size(); ++l)
      level += scene.lights()[l].radiance * reference.visibility(point.position, point.normal, l).unoccludedFactor;
    ++out.points;
    for (int c = 0; c < 3; ++c) {
      if (!(level[c] > 0)) continue;
      const double ratio = std::abs(interpolated[c] - exact[c]) / (tolerance * level[c]);
      out.worst = std::max(out.worst, ratio);
      if (ratio > slack) {
        if (out.over++ == 0)
          out.first = "point (" + std::to_string(point.position.x) + ", " + std::to_string(point.position.y) + ", " +
                      std::to_string(point.position.z) + "): mesh " + std::to_string(interpolated[c]) + " exact " +
                      std::to_string(exact[c]) + " level " + std::to_string(level[c]);
        break;
      }
    }
  }
  return out;
}

// The same at kBoundPoints seeded random points of every receiving face.
inline BoundCheck checkBound(const Engine& engine, const Mesh& mesh, double tolerance, double slack, uint64_t seed) {
  return checkBound(engine, mesh, tolerance, slack, sampleReceivingPoints(engine.scene(), kBoundPoints, seed));
}

// `count` seeded random points of one (convex) face, uniform over its area.
inline std::vector<SurfacePoint> pointsOnFace(const Face& face, size_t count, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  const Polygon3& p = face.polygon;
  std::vector<double> areas;  // the fan's triangles, cumulative
  for (size_t i = 1; i + 1 < p.size(); ++i)
    areas.push_back((areas.empty() ? 0 : areas.back()) + 0.5 * glm::length(glm::cross(p[i] - p[0], p[i + 1] - p[0])));
  std::vector<SurfacePoint> out;
  for (size_t k = 0; k < count; ++k) {
    const size_t t = size_t(std::lower_bound(areas.begin(), areas.end(), unit(rng) * areas.back()) - areas.begin());
    double u = unit(rng), v = unit(rng);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    const size_t i = std::min(t, areas.size() - 1) + 1;
    out.push_back({face.id, p[0] + u * (p[i] - p[0]) + v * (p[i + 1] - p[0]), face.plane.normal});
  }
  return out;
}

// The engine's kept mesh equals its mesh refined afresh (the memo dropped), bit for bit.
inline void expectSameAsAFreshMesh(Engine& engine, const Mesh& kept) {
  engine.forgetMeshMemo();
  const Mesh fresh = engine.mesh();
  ASSERT_EQ(kept.receivers.size(), fresh.receivers.size());
  for (size_t i = 0; i < kept.receivers.size(); ++i) {
    EXPECT_EQ(kept.receivers[i].positions, fresh.receivers[i].positions) << "receiver " << i;
    EXPECT_EQ(kept.receivers[i].irradiance, fresh.receivers[i].irradiance) << "receiver " << i;
    EXPECT_EQ(kept.receivers[i].triangles, fresh.receivers[i].triangles) << "receiver " << i;
  }
}

}  // namespace penumbra::testing
