// Clipping convex 3D polygons by planes: known cases, the eps rule, and area
// conservation of splits on seeded random polygons.
#include "core/geom/clip.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace penumbra {
namespace {

constexpr double kEps = 1e-9;

Polygon3 unitSquareXY() { return {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}; }

TEST(Clip, KeepsFrontHalf) {
  const Plane plane = Plane::throughPoint({1, 0, 0}, {0.25, 0, 0});
  const Polygon3 front = clipFront(unitSquareXY(), plane, kEps);
  EXPECT_NEAR(area(front), 0.75, 1e-15);
  for (const Vec3& v : front) EXPECT_GE(plane.signedDistance(v), -kEps);
  // Same winding as the input.
  EXPECT_GT(glm::dot(newellVector(front), Vec3{0, 0, 1}), 0);
}

TEST(Clip, WholeOrNothing) {
  const Polygon3 square = unitSquareXY();
  EXPECT_EQ(clipFront(square, Plane::throughPoint({1, 0, 0}, {-1, 0, 0}), kEps), square);
  EXPECT_TRUE(clipFront(square, Plane::throughPoint({1, 0, 0}, {2, 0, 0}), kEps).empty());
  // Touching along an edge: nothing of positive area in front.
  EXPECT_TRUE(clipFront(square, Plane::throughPoint({1, 0, 0}, {1, 0, 0}), kEps).empty());
  EXPECT_EQ(clipFront(square, Plane::throughPoint({-1, 0, 0}, {1, 0, 0}), kEps), square);
  // Coplanar: no positive area on either side.
  EXPECT_TRUE(clipFront(square, Plane::throughPoint({0, 0, 1}, {0, 0, 0}), kEps).empty());
  EXPECT_TRUE(clipFront(square, Plane::throughPoint({0, 0, -1}, {0, 0, 0}), kEps).empty());
}

TEST(Clip, VerticesWithinEpsCountAsOnThePlane) {
  // One corner pokes 0.5 eps behind the plane: the polygon is kept unchanged.
  Polygon3 square = unitSquareXY();
  square[1].x = 1 + 0.5 * kEps;
  const Plane plane = Plane::throughPoint({-1, 0, 0}, {1, 0, 0});
  EXPECT_EQ(clipFront(square, plane, kEps), square);
  // Two eps behind: it is cut.
  square[1].x = 1 + 2 * kEps;
  EXPECT_NE(clipFront(square, plane, kEps), square);
  // A triangle with one vertex just in front (within eps) and the rest behind: empty.
  const Polygon3 tri{{-1, 0, 0}, {0.5 * kEps, 0.5, 0}, {-1, 1, 0}};
  EXPECT_TRUE(clipFront(tri, Plane::throughPoint({1, 0, 0}, {0, 0, 0}), kEps).empty());
}

TEST(Clip, RandomSplitsConserveArea) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  int spanning = 0;
  for (int k = 0; k < 600; ++k) {
    // A random convex polygon on a random plane: sorted angles on an ellipse.
    const Vec3 normal = glm::normalize(Vec3{unit(rng), unit(rng), unit(rng)} + Vec3{0, 0, 1e-3});
    Vec3 u = glm::normalize(glm::cross(normal, Vec3{0.3, 0.7, 0.1}));
    Vec3 v = glm::cross(normal, u);
    const Vec3 center{unit(rng), unit(rng), unit(rng)};
    std::vector<double> angles(3 + k % 6);
    for (double& a : angles) a = (unit(rng) + 1) * M_PI;
    std::sort(angles.begin(), angles.end());
    const double rx = 0.2 + std::abs(unit(rng)), ry = 0.2 + std::abs(unit(rng));
    Polygon3 poly;
    for (double a : angles) poly.push_back(center + rx * std::cos(a) * u + ry * std::sin(a) * v);
    const Plane plane = Plane::throughPoint(
        glm::normalize(Vec3{unit(rng), unit(rng), unit(rng)} + Vec3{1e-3, 0, 0}),
        center + 0.5 * Vec3{unit(rng), unit(rng), unit(rng)});

    const Split3 s = splitByPlane(poly, plane, kEps);
    const double whole = area(poly);
    EXPECT_NEAR(area(s.front) + area(s.back), whole, 1e-12 * whole) << "case " << k;
    EXPECT_EQ(clipFront(poly, plane, kEps), s.front) << "case " << k;
    EXPECT_EQ(clipFront(poly, plane.flipped(), kEps), s.back) << "case " << k;
    for (const Vec3& p : s.front) EXPECT_GE(plane.signedDistance(p), -kEps) << "case " << k;
    for (const Vec3& p : s.back) EXPECT_LE(plane.signedDistance(p), kEps) << "case " << k;
    // The pieces stay in the polygon's plane with its winding.
    for (const Polygon3* piece : {&s.front, &s.back}) {
      if (piece->empty()) continue;
      EXPECT_GT(glm::dot(newellVector(*piece), normal), 0) << "case " << k;
      for (const Vec3& p : *piece) EXPECT_NEAR(glm::dot(p - center, normal), 0, 1e-12);
    }
    spanning += !s.front.empty() && !s.back.empty();
  }
  EXPECT_GT(spanning, 100);
}

}  // namespace
}  // namespace penumbra
