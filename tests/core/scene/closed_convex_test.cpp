// Closed convex objects (core/scene/closed_convex.h): seeded random boxes, convex prisms,
// pyramids and UV spheres under random transforms (mirrors included) are detected; a box
// missing a face, a box with one face turned round, an inward box, an L-shaped prism and
// two boxes in one object are not. The scene keeps the property through edits.
#include "core/scene/closed_convex.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/scene/scene.h"
#include "scenegen/scene_parts.h"

namespace penumbra {
namespace {

constexpr int kSeeds = 200;
constexpr double kPi = 3.14159265358979323846;

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

Transform randomTransform(std::mt19937_64& rng) {
  Transform t;
  t.translate = Vec3(uniform(rng, -2, 2), uniform(rng, 0.5, 2), uniform(rng, -2, 2));
  t.rotateDeg = Vec3(uniform(rng, 0, 360), uniform(rng, 0, 360), uniform(rng, 0, 360));
  t.scale = Vec3(uniform(rng, 0.2, 1.5), uniform(rng, 0.2, 1.5), uniform(rng, 0.2, 1.5));
  if (rng() % 4 == 0) t.scale.y = -t.scale.y;  // a mirror: faces keep their front
  return t;
}

// A convex polygon in the xz-plane: `n` sorted random angles on an ellipse, CCW seen from +y.
std::vector<Vec3> convexBase(std::mt19937_64& rng, int n) {
  std::vector<double> angles;
  for (int i = 0; i < n; ++i) angles.push_back(uniform(rng, 0, 2 * kPi));
  std::sort(angles.begin(), angles.end());
  const double a = uniform(rng, 0.3, 1), b = uniform(rng, 0.3, 1);
  std::vector<Vec3> out;
  // Seen from +y, CCW means turning from +z towards +x.
  for (double angle : angles) out.push_back(Vec3(a * std::sin(angle), 0, b * std::cos(angle)));
  return out;
}

// Corners apart and every turn clearly left (CCW seen from +y: cross(d1, d2).y > 0).
bool wellShaped(const std::vector<Vec3>& base) {
  const size_t n = base.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec3 d1 = base[(i + 1) % n] - base[i], d2 = base[(i + 2) % n] - base[(i + 1) % n];
    if (glm::length(d1) < 0.05 || glm::cross(d1, d2).y < 1e-3 * glm::length(d1) * glm::length(d2))
      return false;
  }
  return true;
}

// A prism or a pyramid over a random convex base, outward faces.
Object convexSolid(std::mt19937_64& rng, bool pyramid) {
  std::vector<Vec3> base;
  do base = convexBase(rng, 3 + int(rng() % 6));
  while (!wellShaped(base));
  const int n = int(base.size());
  const double height = uniform(rng, 0.2, 1);
  Object o;
  o.id = "solid";
  o.vertices = base;
  std::vector<int> bottom;  // seen from below (−y): reverse of the CCW-from-above base
  for (int i = n - 1; i >= 0; --i) bottom.push_back(i);
  o.faces.push_back(bottom);
  if (pyramid) {
    o.vertices.push_back(Vec3(uniform(rng, -0.2, 0.2), height, uniform(rng, -0.2, 0.2)));
    for (int i = 0; i < n; ++i) o.faces.push_back({i, (i + 1) % n, n});
    return o;
  }
  for (const Vec3& p : base) o.vertices.push_back(p + Vec3(0, height, 0));
  std::vector<int> top;
  for (int i = 0; i < n; ++i) top.push_back(n + i);
  o.faces.push_back(top);
  for (int i = 0; i < n; ++i) o.faces.push_back({i, (i + 1) % n, n + (i + 1) % n, n + i});
  return o;
}

Object box(std::mt19937_64& rng) {
  Object o;
  o.id = "box";
  const Vec3 lo(uniform(rng, -1, 0), uniform(rng, -1, 0), uniform(rng, -1, 0));
  addBox(o, lo, lo + Vec3(uniform(rng, 0.05, 1), uniform(rng, 0.05, 1), uniform(rng, 0.05, 1)));
  return o;
}

// The same box with a vertex of its own per face corner (as imported meshes often have).
Object unweldedBox(std::mt19937_64& rng) {
  const Object welded = box(rng);
  Object o;
  o.id = "box";
  for (const auto& face : welded.faces) {
    std::vector<int> indices;
    for (int i : face) {
      indices.push_back(int(o.vertices.size()));
      o.vertices.push_back(welded.vertices[size_t(i)]);
    }
    o.faces.push_back(indices);
  }
  return o;
}

// An L-shaped prism: the L extruded along z, its ends each split into two convex
// quads along the diagonal from the outer corner to the inner one.
Object lPrism(std::mt19937_64& rng) {
  const double w = uniform(rng, 0.4, 1), h = uniform(rng, 0.4, 1), t = uniform(rng, 0.1, 0.3);
  const double depth = uniform(rng, 0.2, 1);
  // Outline CCW seen from +z: (0,0) (w,0) (w,t) (t,t) (t,h) (0,h).
  const std::vector<Vec2> outline{{0, 0}, {w, 0}, {w, t}, {t, t}, {t, h}, {0, h}};
  Object o;
  o.id = "ell";
  for (double z : {0.0, depth})
    for (const Vec2& p : outline) o.vertices.push_back(Vec3(p.x, p.y, z));
  const int n = 6;
  o.faces.push_back({n + 0, n + 1, n + 2, n + 3});  // front (z = depth), CCW from +z
  o.faces.push_back({n + 0, n + 3, n + 4, n + 5});
  o.faces.push_back({3, 2, 1, 0});  // back (z = 0), CCW from −z
  o.faces.push_back({5, 4, 3, 0});
  for (int i = 0; i < n; ++i) o.faces.push_back({i, (i + 1) % n, n + (i + 1) % n, n + i});  // sides
  return o;
}

// Scene with the object alone under a small light well above it.
Scene sceneWith(Object object) {
  Light light{"light", {{-0.5, 6, -0.5}, {-0.5, 6, 0.5}, {0.5, 6, 0.5}, {0.5, 6, -0.5}}, Vec3(10)};
  return Scene({light}, {}, {std::move(object)});
}

bool detected(Object object) {
  const Scene scene = sceneWith(std::move(object));
  return scene.isClosedConvex(scene.handleOf(0));
}

TEST(ClosedConvex, RandomConvexSolidsAreDetected) {
  for (int seed = 1; seed <= kSeeds; ++seed) {
    std::mt19937_64 rng{uint64_t(seed)};
    Object solids[] = {box(rng), unweldedBox(rng), convexSolid(rng, false), convexSolid(rng, true)};
    for (Object& o : solids) {
      o.transform = randomTransform(rng);
      EXPECT_TRUE(isClosedOriented(o)) << "seed " << seed << " " << o.faces.size() << " faces";
      EXPECT_TRUE(detected(o)) << "seed " << seed << " " << o.faces.size() << " faces";
    }
  }
}

TEST(ClosedConvex, RandomUvSpheresAreDetected) {
  for (int seed = 1; seed <= kSeeds / 4; ++seed) {
    std::mt19937_64 rng{uint64_t(seed)};
    Object sphere;
    sphere.id = "sphere";
    const int stacks = 2 + int(rng() % 20), slices = 3 + int(rng() % 40);
    addUvSphere(sphere, Vec3(uniform(rng, -1, 1), 0, 0), uniform(rng, 0.05, 1), stacks, slices);
    sphere.transform = randomTransform(rng);
    EXPECT_EQ(sphere.faces.size(), size_t(stacks * slices));
    EXPECT_TRUE(detected(sphere)) << "seed " << seed << ": " << stacks << " × " << slices;
  }
}

TEST(ClosedConvex, OpenMisorientedAndNonConvexAreNot) {
  for (int seed = 1; seed <= kSeeds; ++seed) {
    std::mt19937_64 rng{uint64_t(seed)};
    const Transform transform = randomTransform(rng);
    auto place = [&](Object o) {
      o.transform = transform;
      return o;
    };
    Object open = box(rng);  // a box missing a face
    open.faces.erase(open.faces.begin() + long(rng() % open.faces.size()));
    EXPECT_FALSE(isClosedOriented(open));
    EXPECT_FALSE(detected(place(open))) << "seed " << seed;

    Object turned = convexSolid(rng, rng() % 2 == 0);  // one face turned round
    auto& face = turned.faces[rng() % turned.faces.size()];
    std::reverse(face.begin(), face.end());
    EXPECT_FALSE(isClosedOriented(turned));
    EXPECT_FALSE(detected(place(turned))) << "seed " << seed;

    Object inward = box(rng);  // closed and consistent, but every face facing in
    for (auto& f : inward.faces) std::reverse(f.begin(), f.end());
    EXPECT_TRUE(isClosedOriented(inward));
    EXPECT_FALSE(detected(place(inward))) << "seed " << seed;

    const Object ell = lPrism(rng);  // closed, outward, not convex
    EXPECT_TRUE(isClosedOriented(ell)) << "seed " << seed;
    EXPECT_FALSE(detected(place(ell))) << "seed " << seed;

    Object two = box(rng);  // two closed convex boxes apart, one object
    addBox(two, Vec3(2, 0, 0), Vec3(2.5, 0.5, 0.5));
    EXPECT_TRUE(isClosedOriented(two));
    EXPECT_FALSE(detected(place(two))) << "seed " << seed;
  }
}

// A face plane moved so the box's vertices lie in front of it by less than the scene
// tolerance (rounding) keeps the box convex; by more, it is not.
TEST(ClosedConvex, ConvexityUsesTheSceneTolerance) {
  Object cube;
  cube.id = "cube";
  addBox(cube, Vec3(0), Vec3(1));
  const Scene scene = sceneWith(cube);
  std::vector<Face> faces = scene.facesOf(cube, 0);
  const double eps = scene.tolerance().length();
  EXPECT_TRUE(isConvexWithin(faces, eps));
  Face& top = faces[3];  // +y (addBox: axis 1, side 1)
  ASSERT_GT(top.plane.normal.y, 0.99);
  top.plane.offset += 0.5 * eps;  // the top's own vertices now 0.5 eps in front of it
  EXPECT_TRUE(isConvexWithin(faces, eps));
  top.plane.offset += eps;  // 1.5 eps in front
  EXPECT_FALSE(isConvexWithin(faces, eps));
}

TEST(ClosedConvex, SceneKeepsThePropertyThroughEdits) {
  std::mt19937_64 rng(7);
  Object ell = lPrism(rng);
  Object cube;
  cube.id = "cube";
  addBox(cube, Vec3(0), Vec3(0.5));
  Light light{"light", {{-0.5, 6, -0.5}, {-0.5, 6, 0.5}, {0.5, 6, 0.5}, {0.5, 6, -0.5}}, Vec3(10)};
  Scene scene({light}, {}, {cube, ell});
  EXPECT_TRUE(scene.isClosedConvex(0));
  EXPECT_FALSE(scene.isClosedConvex(1));
  EXPECT_FALSE(scene.mayShadow({0, 1}, {0, 2}));
  EXPECT_TRUE(scene.mayShadow({1, 1}, {1, 2}));
  EXPECT_TRUE(scene.mayShadow({0, 1}, {1, 2}));

  Object open = cube;
  open.id = "open";
  open.faces.pop_back();
  const uint32_t added = scene.addObject(open);
  EXPECT_FALSE(scene.isClosedConvex(added));
  Transform t;
  t.scale = Vec3(1, -2, 0.5);
  t.rotateDeg = Vec3(30, 40, 50);
  scene.setTransform(0, t);
  EXPECT_TRUE(scene.isClosedConvex(0));
  scene.removeObject(1);
  EXPECT_TRUE(scene.isClosedConvex(0));
  EXPECT_FALSE(scene.isClosedConvex(added));
}

}  // namespace
}  // namespace penumbra
