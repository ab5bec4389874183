// Non-convex meshes cast whole from their silhouettes (issue 35): a bumpy sphere, a tilted
// torus and an open bowl floating in the dense room match the exact reference at every DM
// vertex, list the object once per cell instead of face by face, and a frame moving one
// equals a rebuild.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "core/engine/engine.h"
#include "core/scene/mesh_topology.h"
#include "scenegen/dense_scene.h"
#include "scenegen/scene_parts.h"
#include "tests/core/engine/incremental_compare.h"
#include "tests/core/engine/model_room.h"
#include "tests/core/engine/reference_check.h"
#include "tests/core/illum/random_meshes.h"

namespace penumbra {
namespace {

using testing::roomWith;

void expectExact(Engine& engine, const std::string& label) {
  const testing::ReferenceCheck c = testing::checkAgainstReference(engine, label);
  std::printf("%s: %zu vertices, %zu value errors, %zu class errors\n", label.c_str(), c.vertices, c.valueErrors,
              c.classErrors);
  EXPECT_GT(c.vertices, 1000u) << label;
  EXPECT_EQ(c.valueErrors, 0u) << label;
  EXPECT_EQ(c.classErrors, 0u) << label;
}

// Whether some receiver took the object's shadow whole.
bool castWhole(const Engine& engine, uint32_t handle) {
  return !engine.castOn(wholeObject(handle)).empty();
}

TEST(MeshEngine, FloatingNonConvexMeshesMatchReference) {
  const std::vector<std::pair<const char*, Object>> models = {
      {"bumpy sphere", test::bumpySphere("m", {0.3, 1.1, -0.2}, 0.4, 8, 0.3, 5)},
      {"torus", test::torus("m", {0.1, 1.2, 0.2}, 0.45, 0.14, 16, 8, 0.6)},
      {"open bowl", test::bowl("m", {-0.2, 1.3, 0.1}, 0.45, 10, 0.2, 2)},
  };
  for (const auto& [name, model] : models) {
    Engine engine(roomWith({model}));
    const uint32_t handle = engine.scene().handleOf(*engine.scene().findObject("m"));
    ASSERT_NE(engine.scene().meshTopology(handle), nullptr);
    EXPECT_TRUE(castWhole(engine, handle)) << name;
    expectExact(engine, name);
  }
}

// A table as one mesh of 48 faces, its edges parallel to the light's: four slabs side by side
// make the top (faces touching along their sides), four legs touch its underside (T-corners,
// edges along each other seen from below); floating, moved under the light's centre, and
// standing on the floor. Every DM vertex matches the exact reference.
TEST(MeshEngine, AnAxisAlignedTableOfTouchingBoxesMatchesReference) {
  for (int variant = 0; variant < 3; ++variant) {
    Object table;
    table.id = "m";
    table.material = "white";
    const double y = variant == 2 ? 0.0 : 0.6;
    for (int i = 0; i < 2; ++i)
      for (int k = 0; k < 2; ++k)
        addBox(table, Vec3(-0.5 + 0.5 * i, y + 0.7, -0.3 + 0.3 * k),
               Vec3(-0.5 + 0.5 * (i + 1), y + 0.75, -0.3 + 0.3 * (k + 1)));
    for (double x : {-0.45, 0.4})
      for (double z : {-0.25, 0.2}) addBox(table, Vec3(x, y, z), Vec3(x + 0.05, y + 0.7, z + 0.05));
    if (variant == 1)
      for (Vec3& v : table.vertices) v += Vec3(0.2, 0, -0.1);  // the light's centre above its middle
    Engine engine(roomWith({table}));
    const uint32_t handle = engine.scene().handleOf(*engine.scene().findObject("m"));
    ASSERT_NE(engine.scene().meshTopology(handle), nullptr);
    const testing::ReferenceCheck c = testing::checkAgainstReference(engine, "table");
    EXPECT_GT(c.vertices, 700u) << variant;
    EXPECT_EQ(c.valueErrors, 0u) << variant;
    EXPECT_EQ(c.classErrors, 0u) << variant;
  }
}

// The bumpy sphere with every corner below height `floorY` lifted onto it: a flat base
// lying in the floor's plane when the sphere dips below it.
Object flattenedOnto(Object o, double floorY) {
  for (Vec3& v : o.vertices) v.y = std::max(v.y, floorY);
  return o;
}

// The mesh mirrored in the plane y = 0 (faces reversed to keep their sides).
Object upsideDown(Object o) {
  for (Vec3& v : o.vertices) v.y = -v.y;
  for (auto& f : o.faces) std::reverse(f.begin(), f.end());
  return o;
}

// Midpoints of where a triangle mesh meets the plane y = 0 from above: its edges lying in
// the plane beside a face that rises above it, and each face's cut where it crosses.
std::vector<Vec3> contactMidpoints(const Object& o) {
  std::vector<Vec3> out;
  for (const auto& f : o.faces) {
    std::vector<Vec3> onPlane;  // the face's points at y = 0: corners there, edges crossing
    bool above = false;
    for (size_t k = 0; k < f.size(); ++k) {
      const Vec3 &a = o.vertices[size_t(f[k])], &b = o.vertices[size_t(f[(k + 1) % f.size()])];
      above = above || a.y > 1e-12;
      if (std::abs(a.y) <= 1e-12) onPlane.push_back(a);
      else if ((a.y > 0) != (b.y > 0) && std::abs(b.y) > 1e-12) onPlane.push_back(a + (b - a) * (a.y / (a.y - b.y)));
    }
    if (above && onPlane.size() == 2) out.push_back(0.5 * (onPlane[0] + onPlane[1]));
  }
  return out;
}

// How many of `points` lie on no triangle edge of the receiver mesh of face `id`.
size_t offEveryEdge(Engine& engine, FaceId id, const std::vector<Vec3>& points) {
  size_t off = 0;
  for (const Vec3& p : points) {
    bool on = false;
    for (const ReceiverMesh& r : engine.mesh().receivers) {
      if (r.face != id) continue;
      for (const auto& t : r.triangles)
        for (int k = 0; k < 3 && !on; ++k) {
          const Vec3 &a = r.positions[t[k]], &b = r.positions[t[(k + 1) % 3]];
          const double u = std::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
          on = glm::length(a + u * (b - a) - p) < 1e-7;
        }
    }
    off += on ? 0 : 1;
  }
  return off;
}

// Meshes touching the floor (issue 35, resting models): at one corner, with a flat base
// in the floor's plane, sunk through it, and an open bowl standing on its rim edges. Each
// casts on the floor whole, with contact lines where it meets it.
TEST(MeshEngine, RestingMeshesMatchReference) {
  const std::vector<std::pair<const char*, Object>> models = {
      {"sphere on its pole", test::bumpySphere("m", {0.3, 0.4, -0.2}, 0.4, 8, 0.05, 5)},
      {"bumpy sphere dipping in", test::bumpySphere("m", {0.3, 0.4, -0.2}, 0.4, 8, 0.3, 5)},
      {"flat base", flattenedOnto(test::bumpySphere("m", {0.2, 0.3, 0.1}, 0.45, 8, 0.2, 7), 0.0)},
      {"sunk through", test::bumpySphere("m", {-0.1, 0.25, 0.2}, 0.4, 8, 0.2, 11)},
      {"dome on its rim", upsideDown(test::bowl("m", {0.1, 0.0, -0.3}, 0.45, 10, 0.2, 3))},
  };
  for (const auto& [name, model] : models) {
    Engine engine(roomWith({model}));
    const uint32_t handle = engine.scene().handleOf(*engine.scene().findObject("m"));
    ASSERT_NE(engine.scene().meshTopology(handle), nullptr);
    const uint32_t floor = engine.scene().handleOf(*engine.scene().findObject("floor"));
    EXPECT_TRUE(engine.castOn(wholeObject(handle)).count(FaceId{floor, 0})) << name;
    // The contact lines are lines of the floor's mesh (the value jumps across them).
    const std::vector<Vec3> contacts = contactMidpoints(model);
    EXPECT_EQ(offEveryEdge(engine, FaceId{floor, 0}, contacts), 0u) << name << ": " << contacts.size() << " contacts";
    expectExact(engine, name);
  }
}

TEST(MeshEngine, MovesEqualRebuild) {
  Engine engine(roomWith({test::torus("m", {0.1, 1.2, 0.2}, 0.45, 0.14, 16, 8, 0.6),
                          test::bumpySphere("s", {-1.0, 0.8, 0.6}, 0.3, 6, 0.3, 9)}));
  const Vec3 steps[] = {{0.05, 0.0, 0.02}, {0.2, -0.1, 0.0}, {-0.9, 0.1, 0.5}};
  int f = 0;
  for (const Vec3& step : steps) {
    Transform transform;
    transform.translate = step;
    transform.rotateDeg = Vec3(5.0 * f, 10.0 * f, 0);
    const testing::MoveCheck check = testing::moveAndCompareWithRebuild(engine, "m", transform, uint64_t(f));
    EXPECT_FALSE(check.frame.fullRebuild);
    EXPECT_EQ(check.diff.errors(), 0u) << "frame " << f << ": " << check.diff.firstProblem;
    ++f;
  }
  expectExact(engine, "torus after moves");
}

// A model under another (a torus on a shelf below a floating sphere): the torus lies wholly
// behind the planes of the sphere's upper faces, so none of its faces is listed on them; before,
// each of its faces was listed, and failed, on each (a furnished room listed 10 M casts, 1.5 %
// of which could cast). Moving it incrementally (whose casts are not so filtered) equals a
// rebuild, so the faces left out cast nothing.
TEST(MeshEngine, AModelBehindAnothersFacesIsNotListedOnThem) {
  Engine engine(roomWith({test::torus("m", {0.1, 0.35, 0.2}, 0.45, 0.14, 12, 6, 0.2),
                          test::bumpySphere("s", {0.0, 1.4, 0.1}, 0.4, 6, 0.2, 9)}));
  const BuildStats& stats = engine.stats();
  std::printf("%zu receivers, %zu cast attempts, %zu with a shadow\n", stats.receivers,
              stats.castAttempts, stats.pairsWithShadow);
  EXPECT_LT(stats.castAttempts, 4 * stats.receivers);
  Transform transform;
  transform.translate = Vec3(0.1, 0.05, -0.1);
  const testing::MoveCheck check = testing::moveAndCompareWithRebuild(engine, "m", transform, 7);
  EXPECT_FALSE(check.frame.fullRebuild);
  EXPECT_EQ(check.diff.errors(), 0u) << check.diff.firstProblem;
  expectExact(engine, "torus under a sphere");
}

}  // namespace
}  // namespace penumbra
