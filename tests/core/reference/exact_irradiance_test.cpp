// ExactReference against closed forms written independently here (rectangle
// form factors), the single-sided blocking rule, and an independent per-ray
// visibility check on seeded random scenes.
#include "core/reference/exact_irradiance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

namespace penumbra {
namespace {

// ---- Closed forms (independent of lambertFactor) ----------------------------

// Point below a corner of an a×b rectangle in a parallel plane at height h:
// F = 1/(2π)[X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²))], X=a/h, Y=b/h.
double cornerFormFactor(double a, double b, double h) {
  const double x = a / h, y = b / h;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * M_PI);
}

// Signed corner term, so that any rectangle [x0,x1]×[z0,z1] (relative to the
// point's foot) is a sum of four corner rectangles.
double signedCorner(double x, double z, double h) {
  if (x == 0 || z == 0) return 0;
  return (x > 0 ? 1 : -1) * (z > 0 ? 1 : -1) * cornerFormFactor(std::abs(x), std::abs(z), h);
}

// ∫cosθp cosθL / r² dA (= π F) of the parallel rectangle [x0,x1]×[z0,z1] at height h.
double parallelFactor(double x0, double x1, double z0, double z1, double h) {
  return M_PI * (signedCorner(x1, z1, h) - signedCorner(x0, z1, h) - signedCorner(x1, z0, h) +
                 signedCorner(x0, z0, h));
}

// Point on a wall (normal along +x) at height h below a ceiling rectangle
// [0,a] (away from the wall) × [0,b] (along the wall) whose edge meets the wall
// above the point: F = 1/(2π)[atan(b/h) - h/√(h²+a²) atan(b/√(h²+a²))].
// (Integrate x h / r⁴ over x, then over y.)
double perpendicularFormFactor(double a, double b, double h) {
  const double s = std::sqrt(h * h + a * a);
  return (std::atan(b / h) - h / s * std::atan(b / s)) / (2 * M_PI);
}

// ---- Scene building ----------------------------------------------------------

Object quadObject(const std::string& id, const std::array<Vec3, 4>& corners) {
  Object o;
  o.id = id;
  o.vertices.assign(corners.begin(), corners.end());
  o.faces = {{0, 1, 2, 3}};
  return o;
}

// Horizontal quad at height y over [x0,x1]×[z0,z1]; faces up (+y) or down.
Object horizontal(const std::string& id, double y, double x0, double x1, double z0, double z1,
                  bool up) {
  if (up) return quadObject(id, {Vec3{x0, y, z0}, {x0, y, z1}, {x1, y, z1}, {x1, y, z0}});
  return quadObject(id, {Vec3{x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}});
}

// A light at height h over [x0,x1]×[z0,z1], emitting downwards.
Light ceilingLight(double h, double x0, double x1, double z0, double z1, double radiance = 10) {
  return Light{"lamp", {{x0, h, z0}, {x1, h, z0}, {x1, h, z1}, {x0, h, z1}}, Vec3{radiance}};
}

constexpr double kH = 2.0, kA = 0.5, kB = 0.75;  // light height and half sizes
const Vec3 kUp{0, 1, 0};

Scene sceneWith(std::vector<Object> extra, std::vector<Light> lights = {}) {
  if (lights.empty()) lights.push_back(ceilingLight(kH, -kA, kA, -kB, kB));
  extra.push_back(horizontal("floor", 0, -3, 3, -3, 3, true));
  return Scene(std::move(lights), {}, std::move(extra));
}

void expectRelative(double got, double expected, const char* what) {
  EXPECT_NEAR(got, expected, 1e-9 * std::abs(expected)) << what;
}

// ---- Lambert factor ----------------------------------------------------------

TEST(ExactReference, ParallelRectangleCentred) {
  const Scene scene = sceneWith({});
  const ExactReference ref(scene);
  const LightVisibility v = ref.visibility({0, 0, 0}, kUp, 0);
  const double expected = 4 * M_PI * cornerFormFactor(kA, kB, kH);
  expectRelative(v.unoccludedFactor, expected, "unoccluded");
  expectRelative(v.visibleFactor, expected, "visible");
  EXPECT_EQ(v.lightClass, LightClass::Lit);
  const PointIrradiance e = ref.evaluate({0, 0, 0}, kUp);
  for (int c = 0; c < 3; ++c) expectRelative(e.irradiance[c], 10 * expected, "irradiance");
  EXPECT_EQ(e.lightClass, LightClass::Lit);
}

TEST(ExactReference, ParallelRectangleOffCentreAndOutside) {
  const Scene scene = sceneWith({});
  const ExactReference ref(scene);
  for (const Vec3 p : {Vec3{0.2, 0, -0.3}, Vec3{1.3, 0, 0.4}, Vec3{-2.1, 0, -1.7}}) {
    const double expected = parallelFactor(-kA - p.x, kA - p.x, -kB - p.z, kB - p.z, kH);
    expectRelative(ref.visibility(p, kUp, 0).visibleFactor, expected, "off centre");
  }
}

TEST(ExactReference, LambertIgnoresWindingAndIsPositiveInFront) {
  Polygon3 light = ceilingLight(kH, -kA, kA, -kB, kB).polygon;
  const double forward = lambertFactor({0.1, 0, 0.2}, kUp, light);
  std::reverse(light.begin(), light.end());
  EXPECT_GT(forward, 0);
  EXPECT_EQ(lambertFactor({0.1, 0, 0.2}, kUp, light), forward);
}

TEST(ExactReference, PerpendicularWallPoint) {
  // p on a wall x = 0 facing +x; the light's edge x = 0 lies in p's plane.
  const Light light = ceilingLight(kH, 0, 1.2, -0.4, 0.9);
  const Scene scene = sceneWith({quadObject("wall", {Vec3{0, 0, -3}, {0, 3, -3}, {0, 3, 3}, {0, 0, 3}})},
                                {light});
  const ExactReference ref(scene);
  const Vec3 p{0, 0.5, 0}, n{1, 0, 0};
  const double h = kH - p.y;
  const double expected =
      M_PI * (perpendicularFormFactor(1.2, 0.4, h) + perpendicularFormFactor(1.2, 0.9, h));
  const LightVisibility v = ref.visibility(p, n, 0);
  expectRelative(v.unoccludedFactor, expected, "unoccluded");
  expectRelative(v.visibleFactor, expected, "visible (the wall itself never blocks)");
  EXPECT_EQ(v.lightClass, LightClass::Lit);
}

TEST(ExactReference, ReceiverPlaneCutsLightInHalf) {
  // Same wall point, light now straddling the wall plane: only x > 0 counts.
  const Light light = ceilingLight(kH, -1.2, 1.2, -0.4, 0.9);
  const Scene scene = sceneWith({}, {light});
  const ExactReference ref(scene);
  const Vec3 p{0, 0.5, 0}, n{1, 0, 0};
  const double h = kH - p.y;
  const double expected =
      M_PI * (perpendicularFormFactor(1.2, 0.4, h) + perpendicularFormFactor(1.2, 0.9, h));
  const LightVisibility v = ref.visibility(p, n, 0);
  expectRelative(v.unoccludedFactor, expected, "front half only");
  expectRelative(v.visibleFactor, expected, "visible");
  EXPECT_EQ(v.lightClass, LightClass::Lit);
  // The visible piece is the half in front of p.
  ASSERT_EQ(v.visiblePieces.size(), 1u);
  EXPECT_NEAR(area(v.visiblePieces[0]), 1.2 * 1.3, 1e-12);
  for (const Vec3& q : v.visiblePieces[0]) EXPECT_GE(q.x, -scene.tolerance().length());
}

// ---- Occluders ---------------------------------------------------------------

TEST(ExactReference, FullUmbraUnderLargeOccluder) {
  const Scene scene = sceneWith({horizontal("slab", kH / 2, -2.5, 2.5, -2.5, 2.5, true)});
  const ExactReference ref(scene);
  const LightVisibility v = ref.visibility({0.1, 0, -0.2}, kUp, 0);
  const double peak = 4 * M_PI * cornerFormFactor(kA, kB, kH);
  EXPECT_NEAR(v.visibleFactor, 0, 1e-12 * peak);
  EXPECT_TRUE(v.visiblePieces.empty());
  EXPECT_EQ(v.lightClass, LightClass::Umbra);
  expectRelative(v.unoccludedFactor, parallelFactor(-kA - 0.1, kA - 0.1, -kB + 0.2, kB + 0.2, kH),
                 "unoccluded");
  const PointIrradiance e = ref.evaluate({0.1, 0, -0.2}, kUp);
  EXPECT_EQ(e.lightClass, LightClass::Umbra);
  EXPECT_NEAR(e.irradiance.x, 0, 1e-12 * 10 * peak);
}

TEST(ExactReference, BackFacingOccluderDoesNotBlock) {
  // The same slab wound the other way faces the floor, not the light.
  const Scene scene = sceneWith({horizontal("slab", kH / 2, -2.5, 2.5, -2.5, 2.5, false)});
  const ExactReference ref(scene);
  const LightVisibility v = ref.visibility({0.1, 0, -0.2}, kUp, 0);
  expectRelative(v.visibleFactor, parallelFactor(-kA - 0.1, kA - 0.1, -kB + 0.2, kB + 0.2, kH),
                 "visible");
  EXPECT_EQ(v.lightClass, LightClass::Lit);
}

TEST(ExactReference, OccluderEdgeCutsLightAlongALine) {
  // Slab at half height over x >= c/2: from the origin its edge projects to
  // x = c on the light, so exactly [-a, c] × [-b, b] stays visible.
  const double c = 0.2;
  const Scene scene = sceneWith({horizontal("slab", kH / 2, c / 2, 3, -3, 3, true)});
  const ExactReference ref(scene);
  const LightVisibility v = ref.visibility({0, 0, 0}, kUp, 0);
  expectRelative(v.visibleFactor, parallelFactor(-kA, c, -kB, kB, kH), "visible");
  expectRelative(v.unoccludedFactor, parallelFactor(-kA, kA, -kB, kB, kH), "unoccluded");
  EXPECT_EQ(v.lightClass, LightClass::Penumbra);
  double pieceArea = 0;
  for (const Polygon3& piece : v.visiblePieces) pieceArea += area(piece);
  EXPECT_NEAR(pieceArea, (c + kA) * 2 * kB, 1e-12);

  // Half the light exactly: c = 0.
  const Scene half = sceneWith({horizontal("slab", kH / 2, 0, 3, -3, 3, true)});
  const LightVisibility h = ExactReference(half).visibility({0, 0, 0}, kUp, 0);
  expectRelative(h.visibleFactor, 2 * M_PI * cornerFormFactor(kA, kB, kH), "half");
}

TEST(ExactReference, FaceWhosePlaneContainsPointNeverBlocks) {
  // A vertical face standing on the floor beside p, its plane within onPlane of p
  // and facing the light's x > δ side. Were the rule ignored it would hide
  // the light's x ≥ 2δ part from p.
  Scene probe = sceneWith({});
  const double onPlane = probe.tolerance().onPlane();
  auto fin = [](double x) {
    return quadObject("fin", {Vec3{x, 0, -3}, {x, kH / 2, -3}, {x, kH / 2, 3}, {x, 0, 3}});
  };
  {
    const Scene scene = sceneWith({fin(0.5 * onPlane)});
    ASSERT_DOUBLE_EQ(scene.tolerance().onPlane(), onPlane);
    const LightVisibility v = ExactReference(scene).visibility({0, 0, 0}, kUp, 0);
    expectRelative(v.visibleFactor, parallelFactor(-kA, kA, -kB, kB, kH), "not blocked");
    EXPECT_EQ(v.lightClass, LightClass::Lit);
  }
  {
    // Twenty times further away it is a real blocker: visible [-a, 2δ] × [-b, b].
    const double delta = 20 * onPlane;
    const Scene scene = sceneWith({fin(delta)});
    const LightVisibility v = ExactReference(scene).visibility({0, 0, 0}, kUp, 0);
    expectRelative(v.visibleFactor, parallelFactor(-kA, 2 * delta, -kB, kB, kH), "blocked");
    EXPECT_EQ(v.lightClass, LightClass::Penumbra);
  }
}

TEST(ExactReference, FacesInTheLightsPlaneDoNotBlock) {
  // A segment p→q meets such a face only at q, which is on (not strictly in
  // front of) its plane: both windings leave the light whole.
  for (bool up : {true, false}) {
    const Scene scene = sceneWith({horizontal("panel", kH, -0.2, 1.0, -0.3, 0.3, up)});
    const LightVisibility v = ExactReference(scene).visibility({0.1, 0, 0.1}, kUp, 0);
    expectRelative(v.visibleFactor, parallelFactor(-kA - 0.1, kA - 0.1, -kB - 0.1, kB - 0.1, kH),
                   "visible");
    EXPECT_EQ(v.lightClass, LightClass::Lit) << up;
  }
  // Just below the light, facing it, the same panel does block its strip.
  const Scene scene = sceneWith({horizontal("panel", kH - 1e-3, -0.2, 1.0, -0.3, 0.3, true)});
  const LightVisibility v = ExactReference(scene).visibility({0.1, 0, 0.1}, kUp, 0);
  EXPECT_EQ(v.lightClass, LightClass::Penumbra);
  EXPECT_LT(v.visibleFactor, v.unoccludedFactor);
}

TEST(ExactReference, LightsCombine) {
  // Lamp 0 is fully blocked by a slab, lamp 1 is open; lamp 2 emits upwards
  // (its front does not face p) and lamp 3 lies below the floor's plane.
  std::vector<Light> lights{
      ceilingLight(kH, -kA, kA, -kB, kB, 10),
      ceilingLight(kH, 2.0, 2.5, -0.5, 0.5, 3),
      Light{"up", {{-0.2, 1.5, -0.2}, {-0.2, 1.5, 0.2}, {0.2, 1.5, 0.2}, {0.2, 1.5, -0.2}}, Vec3{7}},
      ceilingLight(-0.5, -0.2, 0.2, -0.2, 0.2, 5)};
  lights[1].id = "side";
  lights[3].id = "below";
  const Scene scene = sceneWith({horizontal("slab", kH / 2, -1.0, 1.0, -1.0, 1.0, true)}, lights);
  const ExactReference ref(scene);
  const Vec3 p{0, 0, 0};
  EXPECT_EQ(ref.visibility(p, kUp, 0).lightClass, LightClass::Umbra);
  EXPECT_EQ(ref.visibility(p, kUp, 1).lightClass, LightClass::Lit);
  EXPECT_EQ(ref.visibility(p, kUp, 2).unoccludedFactor, 0);
  EXPECT_EQ(ref.visibility(p, kUp, 3).unoccludedFactor, 0);
  const PointIrradiance e = ref.evaluate(p, kUp);
  EXPECT_EQ(e.lightClass, LightClass::Penumbra);
  expectRelative(e.irradiance.y, 3 * parallelFactor(2.0, 2.5, -0.5, 0.5, kH), "sum");

  // Only the open lamp and the two that do not count: still Lit.
  const Scene open = sceneWith({}, {lights[1], lights[2], lights[3]});
  EXPECT_EQ(ExactReference(open).evaluate(p, kUp).lightClass, LightClass::Lit);
  // No light in front at all: no light, umbra.
  const Scene dark = sceneWith({}, {lights[2], lights[3]});
  const PointIrradiance d = ExactReference(dark).evaluate(p, kUp);
  EXPECT_EQ(d.irradiance, Vec3{0.0});
  EXPECT_EQ(d.lightClass, LightClass::Umbra);
}

// ---- Random scenes: per-ray agreement ----------------------------------------

// Independent blocking test (SCENE_FORMAT.md): segment p→q is blocked by F iff
// it crosses F and q is strictly in front of F's plane; never when F's plane
// contains p (within onPlane).
bool segmentBlocked(const Scene& scene, const Vec3& p, const Vec3& q) {
  for (const Face& f : scene.faces()) {
    const double dp = f.plane.signedDistance(p), dq = f.plane.signedDistance(q);
    if (!(dp < -scene.tolerance().onPlane()) || !(dq > 0)) continue;
    const Vec3 x = p + (q - p) * (dp / (dp - dq));
    bool inside = true;
    for (size_t i = 0; i < f.polygon.size() && inside; ++i) {
      const Vec3 a = f.polygon[i], b = f.polygon[(i + 1) % f.polygon.size()];
      inside = glm::dot(glm::cross(b - a, x - a), f.plane.normal) >= 0;
    }
    if (inside) return true;
  }
  return false;
}

Scene randomScene(std::mt19937& rng, int occluders) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Object> objects;
  for (int k = 0; k < occluders; ++k) {
    // A random convex polygon (sorted angles on an ellipse) on a random plane
    // between the floor and the light.
    Vec3 n = glm::normalize(Vec3{u(rng), u(rng), u(rng)} + Vec3{0, 0.01, 0});
    const Vec3 t = glm::normalize(glm::cross(n, Vec3{0.3, 0.2, 0.9}));
    const Vec3 s = glm::cross(n, t);
    const Vec3 c{u(rng) * 1.2, 1.0 + 0.8 * u(rng), u(rng) * 1.2};
    std::vector<double> angles(3 + k % 4);
    for (double& a : angles) a = (u(rng) + 1) * M_PI;
    std::sort(angles.begin(), angles.end());
    Object o;
    o.id = "occ" + std::to_string(k);
    const double rx = 0.2 + 0.4 * std::abs(u(rng)), ry = 0.2 + 0.4 * std::abs(u(rng));
    for (double a : angles) o.vertices.push_back(c + rx * std::cos(a) * t + ry * std::sin(a) * s);
    o.faces.push_back({});
    for (int i = 0; i < int(angles.size()); ++i) o.faces.back().push_back(i);
    objects.push_back(std::move(o));
  }
  return sceneWith(std::move(objects));
}

TEST(ExactReference, RandomScenesAgreeWithPerRayVisibility) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(0, 1);
  int penumbra = 0, mismatches = 0, samples = 0;
  for (int sceneIndex = 0; sceneIndex < 30; ++sceneIndex) {
    const Scene scene = randomScene(rng, 2 + sceneIndex % 5);
    const ExactReference ref(scene);
    const Light& light = scene.lights()[0];
    for (int k = 0; k < 10; ++k) {
      const Vec3 p{(u(rng) * 2 - 1) * 1.5, 0, (u(rng) * 2 - 1) * 1.5};
      // Every other point is tilted so that its plane may cut the light.
      const Vec3 n = k % 2 ? kUp
                           : glm::normalize(kUp + 1.5 * Vec3{u(rng) * 2 - 1, 0, u(rng) * 2 - 1});
      const LightVisibility v = ref.visibility(p, n, 0);
      if (v.unoccludedFactor == 0) continue;  // the light is wholly behind the tilted plane
      EXPECT_LE(v.visibleFactor, v.unoccludedFactor * (1 + 1e-12));
      EXPECT_GE(v.visibleFactor, 0);
      if (v.lightClass == LightClass::Lit) {
        EXPECT_NEAR(v.visibleFactor, v.unoccludedFactor, 1e-12 * v.unoccludedFactor);
      }
      if (v.lightClass == LightClass::Umbra) {
        EXPECT_EQ(v.visibleFactor, 0);
      }
      penumbra += v.lightClass == LightClass::Penumbra;
      // Uniform light points: inside a visible piece iff the segment is unblocked.
      for (int s = 0; s < 200; ++s) {
        const Vec3 q = light.polygon[0] + u(rng) * (light.polygon[1] - light.polygon[0]) +
                       u(rng) * (light.polygon[3] - light.polygon[0]);
        bool inPiece = false;
        for (const Polygon3& piece : v.visiblePieces) {
          bool inside = true;
          for (size_t i = 0; i < piece.size() && inside; ++i) {
            const Vec3 a = piece[i], b = piece[(i + 1) % piece.size()];
            inside = glm::dot(glm::cross(b - a, q - a), Vec3{0, -1, 0}) >= 0;
          }
          inPiece |= inside;
        }
        ++samples;
        const bool seen = glm::dot(n, q - p) > 0 && !segmentBlocked(scene, p, q);
        mismatches += inPiece != seen;
      }
    }
  }
  EXPECT_GT(penumbra, 20);
  EXPECT_GT(samples, 40000);
  // A random sample lands within rounding of a shadow edge with probability ~0.
  EXPECT_EQ(mismatches, 0) << "of " << samples;
}

// ---- Timing (printed, never asserted) ----------------------------------------

TEST(ExactReference, TimePerPointOnHundredFaceScene) {
  // 16 boxes (6 faces each) on a floor under one light: 97 faces.
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Object> objects;
  for (int k = 0; k < 16; ++k) {
    Object box;
    box.id = "box" + std::to_string(k);
    box.vertices = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                    {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
    box.faces = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
    box.transform.translate = Vec3{2.5 * u(rng), 0.2 + 0.5 * (u(rng) + 1), 2.5 * u(rng)};
    box.transform.rotateDeg = Vec3{0, 90 * u(rng), 0};
    box.transform.scale = Vec3{0.2};
    objects.push_back(std::move(box));
  }
  const Scene scene = sceneWith(std::move(objects));
  ASSERT_EQ(scene.faces().size(), 97u);
  const ExactReference ref(scene);
  const int points = 2000;
  double sum = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < points; ++k)
    sum += ref.evaluate({2.9 * u(rng), 0, 2.9 * u(rng)}, kUp).irradiance.x;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("[ timing ] exact reference, 97 faces, 1 light: %.2f us/point (sum %.6g)\n",
              1e6 * seconds / points, sum);
  EXPECT_GT(sum, 0);
}

}  // namespace
}  // namespace penumbra
