// The shaft between two convex polygons (shaft.h) is their convex hull: on seeded pairs (a light
// over a receiver, tilted, small beside large, one reaching past the other, sharing a plane),
// every convex combination of their corners lies inside every side, and a point just beyond the
// hull's support in a random direction (the support function: the largest u·x over the
// corners, nothing of the shaft's own planes) lies outside some side.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/geom/shaft.h"

namespace penumbra {
namespace {

// A convex polygon of `corners` corners at distance `size` around `centre` in the plane with
// unit normal n, counter-clockwise seen from n, its angles jittered.
Polygon3 convexAround(std::mt19937_64& rng, const Vec3& centre, const Vec3& n, double size, int corners) {
  std::uniform_real_distribution<double> unit(0, 1);
  const Vec3 u = glm::normalize(glm::cross(std::abs(n.y) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0), n));
  const Vec3 v = glm::cross(n, u);
  Polygon3 out;
  for (int k = 0; k < corners; ++k) {
    // Equal angles with one radius per polygon keep it convex; the radius varies by polygon.
    const double angle = 2 * M_PI * (k + 0.3 * unit(rng) / corners) / corners;
    out.push_back(centre + size * (std::cos(angle) * u + std::sin(angle) * v));
  }
  return out;
}

Vec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0, 1);
  return glm::normalize(Vec3(g(rng), g(rng), g(rng)));
}

TEST(Shaft, IsTheHullOfBothPolygons) {
  const double eps = 1e-9;
  size_t outsideFound = 0, probes = 0;  // probes beyond the support, and how many were rejected
  for (uint64_t seed = 1; seed <= 300; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1), u(-1, 1);
    const int kind = int(seed % 4);
    // A light facing down at y = 3 and a receiver below it, tilted at random; kinds: small
    // receiver, a large one reaching past the light, one nearly on its side, and both in one plane.
    const Polygon3 light = convexAround(rng, {u(rng), 3, u(rng)}, {0, -1, 0}, 0.5, 3 + int(seed % 3));
    Vec3 normal = glm::normalize(Vec3(0, 1, 0) + 0.6 * randomUnit(rng));
    Vec3 centre{2 * u(rng), 1 + unit(rng), 2 * u(rng)};
    double size = kind == 1 ? 3.0 : 0.05 + 0.3 * unit(rng);
    if (kind == 2) normal = glm::normalize(Vec3(1, 0.02, 0));
    if (kind == 3) normal = {0, 1, 0}, centre.y = 3;  // in the light's plane, beside it
    const Polygon3 receiver = convexAround(rng, centre, normal, size, 3 + int(seed % 2));
    const Shaft shaft = shaftBetween(light, receiver, eps);
    // Both in one plane: the hull is flat and no candidate plane has a side (nothing known).
    ASSERT_EQ(shaft.sides.empty(), kind == 3) << "seed " << seed;
    // Inside: convex combinations of the corners of both.
    for (int k = 0; k < 50; ++k) {
      Vec3 x{0.0};
      double total = 0;
      for (const Polygon3* polygon : {&light, &receiver})
        for (const Vec3& v : *polygon) {
          const double w = unit(rng);
          x += w * v;
          total += w;
        }
      x /= total;
      for (const Plane& side : shaft.sides) ASSERT_GE(side.signedDistance(x), -4 * eps) << "seed " << seed;
      EXPECT_FALSE(shaft.ballOutside(x, 0.0, 4 * eps));
    }
    // Outside: beyond the support of the corners in direction d, by 1e-6.
    for (int k = 0; k < 50; ++k) {
      const Vec3 d = randomUnit(rng);
      Vec3 far = light[0];
      double best = -INFINITY;
      for (const Polygon3* polygon : {&light, &receiver})
        for (const Vec3& v : *polygon)
          if (glm::dot(d, v) > best) best = glm::dot(d, v), far = v;
      const Vec3 x = far + 1e-6 * d;
      const bool outside = shaft.ballOutside(x, 0.0, 0.0);
      if (kind == 3) continue;
      EXPECT_TRUE(outside) << "seed " << seed << " direction " << d.x << " " << d.y << " " << d.z;
      outsideFound += outside;
      ++probes;
    }
  }
  EXPECT_EQ(outsideFound, probes);
  EXPECT_GT(probes, 10000u);
}

TEST(Shaft, DegeneratePolygonsKnowNothing) {
  const Polygon3 light{{0, 3, 0}, {1, 3, 0}, {1, 3, 1}};
  EXPECT_TRUE(shaftBetween(light, Polygon3{{0, 0, 0}, {1, 0, 0}}, 1e-9).sides.empty());
  // Three corners on a line: no side of its own; what is kept still holds both.
  const Polygon3 line{{0, 0, 0}, {0.5, 0, 0}, {1, 0, 0}};
  const Shaft shaft = shaftBetween(light, line, 1e-9);
  for (const Plane& side : shaft.sides) {
    for (const Vec3& v : light) EXPECT_GE(side.signedDistance(v), -1e-9);
    for (const Vec3& v : line) EXPECT_GE(side.signedDistance(v), -1e-9);
  }
}

}  // namespace
}  // namespace penumbra
