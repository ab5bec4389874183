// ConvexSilhouette against the silhouette's definition on seeded random boxes (an
// edge is on the silhouette from s iff s is in front of exactly one of its two
// faces, a corner iff the light edge is behind one of its faces somewhere), and the
// engine with the filter: every DM vertex still equals the exact reference, with fewer
// vertices than every line gives.
#include "core/shadow/convex_silhouette.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/engine/engine.h"
#include "scenegen/dense_scene.h"
#include "scenegen/scene_parts.h"
#include "scenegen/sphere_scene.h"
#include "tests/core/engine/reference_check.h"

namespace penumbra {
namespace {

// One box of random sides, turned about all three axes, and a light far away (the
// light only makes the scene valid; the test draws its own light points).
Scene randomBox(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> side(0.2, 1.0), angle(0.0, 360.0);
  Object box;
  box.id = "box";
  addBox(box, Vec3(0.0), Vec3(side(rng), side(rng), side(rng)));
  box.transform.rotateDeg = Vec3(angle(rng), angle(rng), angle(rng));
  const Light light = squareCeilingLight("light", Vec3(0, 5, 0), 1.0, 0, Vec3(1, 0, 0));
  return Scene({light}, {}, {box});
}

bool near(const Vec3& a, const Vec3& b) { return glm::length(a - b) < 1e-12; }
bool holds(const Face& face, const Vec3& p) {
  return std::any_of(face.polygon.begin(), face.polygon.end(), [&](const Vec3& q) { return near(p, q); });
}
// Whether s is clearly on one side of the plane (far from the tolerances at stake).
bool clear(const Plane& plane, const Vec3& s) { return std::abs(plane.signedDistance(s)) > 1e-3; }
bool front(const Plane& plane, const Vec3& s) { return plane.signedDistance(s) > 0; }

TEST(ConvexSilhouette, EdgesFollowTheDefinition) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> coordinate(-3.0, 3.0);
  int dropped = 0, silhouettes = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const Scene scene = randomBox(rng);
    const auto faces = scene.facesOfObject(scene.handleOf(0));
    ASSERT_EQ(faces.size(), 6u);
    const ConvexSilhouette silhouette(faces, scene.tolerance());
    for (const Face& f : faces)
      for (size_t i = 0; i < f.polygon.size(); ++i) {
        const Vec3 a = f.polygon[i], b = f.polygon[(i + 1) % f.polygon.size()];
        const auto g = std::find_if(faces.begin(), faces.end(),
                                    [&](const Face& h) { return &h != &f && holds(h, a) && holds(h, b); });
        ASSERT_NE(g, faces.end());
        for (int k = 0; k < 20; ++k) {
          const Vec3 s(coordinate(rng), coordinate(rng), coordinate(rng));
          if (!clear(f.plane, s) || !clear(g->plane, s)) continue;
          const bool onSilhouette = front(f.plane, s) != front(g->plane, s);
          const bool bothFront = front(f.plane, s) && front(g->plane, s);
          const bool kept = silhouette.mayBeSilhouette({a, b}, {s, s});
          // A silhouette edge is never dropped; an edge with s in front of both faces is.
          if (onSilhouette) EXPECT_TRUE(kept) << "trial " << trial;
          if (bothFront) EXPECT_FALSE(kept) << "trial " << trial;
          dropped += !kept;
          silhouettes += onSilhouette;
        }
      }
  }
  std::printf("edges: %d dropped, %d on a silhouette\n", dropped, silhouettes);
  EXPECT_GT(dropped, 100);
  EXPECT_GT(silhouettes, 100);
}

TEST(ConvexSilhouette, CornersFollowTheDefinition) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> coordinate(-3.0, 3.0), t(0.0, 1.0);
  int dropped = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const Scene scene = randomBox(rng);
    const auto faces = scene.facesOfObject(scene.handleOf(0));
    const ConvexSilhouette silhouette(faces, scene.tolerance());
    for (const Vec3& v : faces[0].polygon) {
      std::vector<const Face*> around;
      for (const Face& f : faces)
        if (holds(f, v)) around.push_back(&f);
      ASSERT_EQ(around.size(), 3u);
      for (int k = 0; k < 20; ++k) {
        const Vec3 p(coordinate(rng), coordinate(rng), coordinate(rng));
        const Vec3 q(coordinate(rng), coordinate(rng), coordinate(rng));
        if (std::any_of(around.begin(), around.end(),
                        [&](const Face* f) { return !clear(f->plane, p) || !clear(f->plane, q); }))
          continue;
        // Some point of pq behind some face through v: v is on the silhouette from there
        // (or the whole corner faces away), and the surface must stay.
        bool everywhereFront = true;
        for (int j = 0; j <= 64; ++j) {
          const Vec3 x = p + (double(j) / 64) * (q - p);
          for (const Face* f : around) everywhereFront = everywhereFront && front(f->plane, x);
        }
        const bool kept = silhouette.mayBeSilhouette({v, v}, {p, q});
        EXPECT_EQ(kept, !everywhereFront) << "trial " << trial;
        dropped += !kept;
      }
    }
  }
  std::printf("corners: %d dropped\n", dropped);
  EXPECT_GT(dropped, 20);
}

TEST(ConvexSilhouette, PointsOnOneFaceAreKept) {
  std::mt19937_64 rng(13);
  const Scene scene = randomBox(rng);
  const auto faces = scene.facesOfObject(scene.handleOf(0));
  const ConvexSilhouette silhouette(faces, scene.tolerance());
  const Face& f = faces[0];
  // An edge made by clipping the face (its ends inside two of its edges), and a point
  // inside it, seen from far in front of every face's plane... of this face only.
  const Vec3 a = 0.5 * (f.polygon[0] + f.polygon[1]), b = 0.5 * (f.polygon[1] + f.polygon[2]);
  const Vec3 s = a + 100.0 * f.plane.normal;
  EXPECT_TRUE(silhouette.mayBeSilhouette({a, b}, {s, s}));
  EXPECT_TRUE(silhouette.mayBeSilhouette({0.5 * (a + b), 0.5 * (a + b)}, {s, s}));
}

size_t dmVertexCount(const Engine& engine) {
  size_t n = 0;
  for (const Engine::Receiver& r : engine.receivers()) n += r.tree.vertices().size();
  return n;
}

// The filtered DM against the independent exact reference at every vertex (its cells
// are a BSP's, so its vertices are not a subset of the unfiltered DM's: lines extend
// across cells that no longer split), with fewer vertices than every line gives.
void expectExactWithFewerVertices(const Scene& scene, const std::string& label) {
  // Face by face both (a closed object cast whole is object_shadow_test's).
  EngineSettings all, silhouette;
  all.silhouetteLinesOnly = false;
  all.closedObjectsAsOne = silhouette.closedObjectsAsOne = false;
  Engine filtered(scene, silhouette);
  const Engine unfiltered(scene, all);
  const testing::ReferenceCheck c = testing::checkAgainstReference(filtered, label);
  const size_t every = dmVertexCount(unfiltered);
  std::printf("%s: %zu DM vertices with every line, %zu with silhouette lines only\n", label.c_str(), every,
              c.vertices);
  EXPECT_EQ(c.valueErrors, 0u) << label;
  EXPECT_EQ(c.classErrors, 0u) << label;
  EXPECT_LT(c.vertices, every) << label;
}

TEST(SilhouetteLines, DenseRoomsStayExactWithFewerVertices) {
  for (uint64_t seed = 1; seed <= 3; ++seed)
    expectExactWithFewerVertices(makeDenseScene({.boxes = 20, .seed = seed}), "dense 20 seed " + std::to_string(seed));
}

TEST(SilhouetteLines, SphereStaysExactWithFewerVertices) {
  expectExactWithFewerVertices(makeSphereScene({.faces = 288, .radius = 0.35, .centre = Vec3(0.4, 0.7, -0.3)}), "sphere 288");
}

}  // namespace
}  // namespace penumbra
