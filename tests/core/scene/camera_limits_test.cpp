// validateCamera (core/scene/camera_limits.h): each limit holds at its edge and refuses just past
// it, naming the field; the default camera of any scene size passes; and, seeded, every camera it
// accepts gives finite primary rays Embree takes (components within 1.8e18), the property that
// keeps its ray assertion out of reach (issue 36).
#include "core/scene/camera_limits.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/raycast/camera_projection.h"

namespace penumbra {
namespace {

Bounds unitBox(double size, const Vec3& centre = Vec3(0.0)) {
  return Bounds{centre - Vec3(size / 2), centre + Vec3(size / 2)};
}

std::string refusedKey(const Camera& camera, const Bounds& bounds) {
  try {
    validateCamera(camera, bounds);
  } catch (const CameraError& error) {
    return error.key();
  }
  return "";
}

TEST(CameraLimits, TheDefaultCameraOfAnySceneSizePasses) {
  for (double size : {1e-4, 1e-2, 1.0, 1e3, 1e6})
    for (const Vec3& centre : {Vec3(0.0), Vec3(1e3, -2e2, 5e3)}) {
      const Bounds bounds = unitBox(size, centre);
      EXPECT_EQ(refusedKey(defaultCamera(bounds), bounds), "") << size;
    }
}

TEST(CameraLimits, EachLimitHoldsAtItsEdgeAndRefusesPastItNamingTheField) {
  const Bounds bounds = unitBox(1.0);
  const double size = bounds.diagonal();
  Camera base = defaultCamera(bounds);
  auto with = [&](auto change) {
    Camera c = base;
    change(c);
    return refusedKey(c, bounds);
  };
  EXPECT_EQ(with([](Camera& c) { c.fovYDeg = CameraLimits::kMinFovYDeg; }), "");
  EXPECT_EQ(with([](Camera& c) { c.fovYDeg = 0.999 * CameraLimits::kMinFovYDeg; }), "fov_y_deg");
  EXPECT_EQ(with([](Camera& c) { c.fovYDeg = CameraLimits::kMaxFovYDeg; }), "");
  EXPECT_EQ(with([](Camera& c) { c.fovYDeg = 179.001; }), "fov_y_deg");
  EXPECT_EQ(with([](Camera& c) { c.fovYDeg = NAN; }), "fov_y_deg");
  EXPECT_EQ(
      with([&](Camera& c) { c.near = 1e-3, c.far = 0.999e-3 * CameraLimits::kMaxDepthRatio; }), "");
  EXPECT_EQ(with([&](Camera& c) { c.near = 1e-3, c.far = 1.01e-3 * CameraLimits::kMaxDepthRatio; }),
            "near");
  EXPECT_EQ(with([&](Camera& c) { c.near = 0.99 * CameraLimits::kMinNear * size, c.far = 1; }),
            "near");
  EXPECT_EQ(
      with([&](Camera& c) { c.far = 1.01 * CameraLimits::kMaxFar * size, c.near = c.far / 100; }),
      "far");
  EXPECT_EQ(with([](Camera& c) { c.far = c.near; }), "far");
  EXPECT_EQ(with([](Camera& c) { c.near = -0.0; }), "near");
  EXPECT_EQ(with([](Camera& c) { c.far = INFINITY; }), "far");
  EXPECT_EQ(
      with([&](Camera& c) { c.position = Vec3(1.01 * CameraLimits::kMaxReach * size, 0, 0); }),
      "position");
  EXPECT_EQ(with([&](Camera& c) { c.target = Vec3(0, -1.01 * CameraLimits::kMaxReach * size, 0); }),
            "target");
  EXPECT_EQ(with([](Camera& c) { c.target = c.position; }), "target");
  EXPECT_EQ(with([](Camera& c) { c.up = c.target - c.position; }), "up");
  EXPECT_EQ(with([](Camera& c) { c.up = Vec3(0.0); }), "up");
  EXPECT_EQ(with([](Camera& c) { c.up = Vec3(0, NAN, 0); }), "up");
  base.projection = Camera::Projection::Orthographic;
  EXPECT_EQ(with([&](Camera& c) { c.height = CameraLimits::kMinOrthoHeight * size; }), "");
  EXPECT_EQ(with([&](Camera& c) { c.height = 0.99 * CameraLimits::kMinOrthoHeight * size; }),
            "height");
  EXPECT_EQ(with([&](Camera& c) { c.height = 1.01 * CameraLimits::kMaxOrthoHeight * size; }),
            "height");
  EXPECT_EQ(with([](Camera& c) { c.fovYDeg = 1e-300; }), "")
      << "an orthographic view ignores its fov";
}

bool embreeTakes(const Vec3& v) {
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(float(v[c])) || std::fabs(float(v[c])) > 1.8e18f) return false;
  return true;
}

// Seeded: cameras from extreme and ordinary values; every one accepted projects and gives rays
// through the image's corners and centre that Embree takes.
TEST(CameraLimits, EveryAcceptedCameraGivesRaysEmbreeTakes) {
  const double values[] = {0.0, -0.0, 4.9e-324, 1e-300, 1e-12, 1e-7, 1e-3, 0.01, 0.5,   1,     3,
                           -2,  45,   179,      1e3,    1e5,   1e7,  1e12, 1e19, 1e300, -1e300};
  std::mt19937 rng(36);
  auto pick = [&] {
    return rng() % 3 ? values[rng() % std::size(values)]
                     : std::uniform_real_distribution(-5.0, 5.0)(rng);
  };
  size_t accepted = 0;
  for (int i = 0; i < 20000; ++i) {
    const Bounds bounds = unitBox(std::pow(10.0, int(rng() % 9) - 4));
    Camera c = defaultCamera(bounds);
    switch (rng() % 4) {  // a few fields at a time, so that many cameras pass
      case 0:
        c.near = pick(), c.far = pick();
        break;
      case 1:
        c.position = Vec3(pick(), pick(), pick()) * bounds.diagonal();
        break;
      case 2:
        c.projection = Camera::Projection::Orthographic, c.height = pick();
        break;
      default:
        c.fovYDeg = pick(), c.up = Vec3(pick(), pick(), pick());
        break;
    }
    if (!refusedKey(c, bounds).empty()) continue;
    ++accepted;
    const CameraProjection projection(c, 7, 5);
    for (const Vec2 pixel : {Vec2(0, 0), Vec2(7, 5), Vec2(3.5, 2.5), Vec2(7, 0)}) {
      const CameraProjection::Ray ray = projection.rayThrough(pixel);
      ASSERT_TRUE(embreeTakes(ray.origin) && embreeTakes(ray.dir))
          << "near " << c.near << " far " << c.far << " fov " << c.fovYDeg << " height "
          << c.height;
    }
  }
  EXPECT_GT(accepted, 2000u);
}

}  // namespace
}  // namespace penumbra
