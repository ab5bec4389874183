// PlaneFrame: orthonormal, right-handed about the plane normal, exact round trips.
#include "core/geom/plane_frame.h"

#include <gtest/gtest.h>

#include <random>

#include "core/geom/convex2d.h"
#include "core/geom/polygon.h"

namespace penumbra {
namespace {

TEST(PlaneFrame, RoundTripsAndKeepsOrientation) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int k = 0; k < 500; ++k) {
    Vec3 n{unit(rng), unit(rng), unit(rng)};
    if (k % 5 == 0) n = Vec3{0, k % 2 ? 1.0 : -1.0, 0};  // axis-aligned planes too
    if (glm::length(n) < 1e-3) continue;
    n = glm::normalize(n);
    const Plane plane = Plane::throughPoint(n, Vec3{unit(rng), unit(rng), unit(rng)} * 3.0);
    const PlaneFrame frame = PlaneFrame::onPlane(plane, Vec3{unit(rng), unit(rng), unit(rng)});
    EXPECT_NEAR(glm::length(frame.u), 1, 1e-15);
    EXPECT_NEAR(glm::length(frame.v), 1, 1e-15);
    EXPECT_NEAR(glm::dot(frame.u, frame.v), 0, 1e-15);
    EXPECT_NEAR(glm::length(glm::cross(frame.u, frame.v) - n), 0, 1e-15);
    EXPECT_NEAR(plane.signedDistance(frame.origin), 0, 1e-14);

    // A CCW triangle about n stays CCW in 2D, with the same area.
    const Vec3 a = plane.project(Vec3{unit(rng), unit(rng), unit(rng)});
    const Vec3 b = plane.project(Vec3{unit(rng), unit(rng), unit(rng)});
    const Vec3 c = plane.project(Vec3{unit(rng), unit(rng), unit(rng)});
    Polygon3 tri{a, b, c};
    if (glm::dot(newellVector(tri), n) < 0) std::swap(tri[1], tri[2]);
    const Polygon2 flat{frame.to2D(tri[0]), frame.to2D(tri[1]), frame.to2D(tri[2])};
    EXPECT_NEAR(signedArea(flat), area(tri), 1e-12);
    for (const Vec3& p : tri) EXPECT_NEAR(glm::length(frame.to3D(frame.to2D(p)) - p), 0, 1e-14);
  }
}

}  // namespace
}  // namespace penumbra
