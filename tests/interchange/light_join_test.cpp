// Emissive triangles of one group that form a flat convex polygon become one light
// (`coplanar_light_triangles_joined`); pairs that are not convex or not coplanar stay
// two lights. Seeded: random convex polygons, triangulated, shuffled and written as
// OBJ come back as the one polygon.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "core/geom/plane_frame.h"
#include "core/geom/polygon.h"
#include "interchange/obj_import.h"

namespace penumbra::interchange {
namespace {

const std::string kMtl = "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKe 5 4 3\n";

// A floor under the lamp; the lamp's triangles as given (one 'v' per corner of each
// triangle when `ownCorners`, else the polygon's corners once, shared).
std::string objWithLamp(const Polygon3& corners, const std::vector<IndexPolygon>& triangles, bool ownCorners) {
  std::ostringstream o;
  o.precision(17);
  o << "mtllib m.mtl\no floor\nusemtl grey\nv -2 0 -2\nv -2 0 2\nv 2 0 2\nv 2 0 -2\nf 1 2 3 4\n";
  o << "o lamp\nusemtl lamp\n";
  int next = 5;
  if (!ownCorners) {
    for (const Vec3& p : corners) o << "v " << p.x << " " << p.y << " " << p.z << "\n";
    for (const IndexPolygon& t : triangles) o << "f " << next + t[0] << " " << next + t[1] << " " << next + t[2] << "\n";
    return o.str();
  }
  for (const IndexPolygon& t : triangles) {
    for (int i : t) o << "v " << corners[size_t(i)].x << " " << corners[size_t(i)].y << " " << corners[size_t(i)].z << "\n";
    o << "f " << next << " " << next + 1 << " " << next + 2 << "\n";
    next += 3;
  }
  return o.str();
}

ImportResult importText(const std::string& obj) { return importObjText(obj, {{"m.mtl", kMtl}}, {}, "lamp.obj"); }

// The same cycle of points, starting anywhere.
bool sameCycle(const Polygon3& a, const Polygon3& b) {
  if (a.size() != b.size()) return false;
  for (size_t start = 0; start < a.size(); ++start) {
    bool all = true;
    for (size_t k = 0; k < a.size() && all; ++k) all = a[(start + k) % a.size()] == b[k];
    if (all) return true;
  }
  return false;
}

// A quad lamp at y = 3 facing down (counter-clockwise seen from below).
const Polygon3 kQuad = {{-0.5, 3, -0.5}, {0.5, 3, -0.5}, {0.5, 3, 0.5}, {-0.5, 3, 0.5}};

TEST(LightJoin, ObjQuadLightAsTwoTrianglesIsOneLight) {
  for (bool ownCorners : {false, true}) {
    const ImportResult result = importText(objWithLamp(kQuad, {{0, 1, 2}, {0, 2, 3}}, ownCorners));
    EXPECT_EQ(result.report.repaired("coplanar_light_triangles_joined"), 1u) << result.report.summary();
    EXPECT_EQ(result.report.lights, 1u);
    ASSERT_EQ(result.scene.lights().size(), 1u);
    EXPECT_TRUE(sameCycle(result.scene.lights()[0].polygon, kQuad));
    EXPECT_EQ(result.scene.lights()[0].radiance, Vec3(5, 4, 3));
    EXPECT_EQ(result.report.repaired("lights_turned_to_face_the_scene"), 0u);
  }
}

TEST(LightJoin, TrianglesWoundAwayAreTurnedThenJoinedAndCountedOnce) {
  // Both triangles face up (away from the floor); then one each way.
  const ImportResult up = importText(objWithLamp(kQuad, {{2, 1, 0}, {3, 2, 0}}, false));
  ASSERT_EQ(up.scene.lights().size(), 1u) << up.report.summary();
  EXPECT_TRUE(sameCycle(up.scene.lights()[0].polygon, kQuad));
  EXPECT_EQ(up.report.repaired("lights_turned_to_face_the_scene"), 1u);
  const ImportResult mixed = importText(objWithLamp(kQuad, {{0, 1, 2}, {3, 2, 0}}, false));
  ASSERT_EQ(mixed.scene.lights().size(), 1u) << mixed.report.summary();
  EXPECT_TRUE(sameCycle(mixed.scene.lights()[0].polygon, kQuad));
  EXPECT_EQ(mixed.report.repaired("lights_turned_to_face_the_scene"), 1u);
}

TEST(LightJoin, NonConvexOrNonCoplanarPairsStayTwoLights) {
  // A dart: the second triangle's far corner is inside the first one's reach.
  const Polygon3 dart = {{-0.5, 3, -0.5}, {0.5, 3, -0.5}, {0, 3, -0.2}, {-0.5, 3, 0.5}};
  // A hinge: the second triangle folded 0.1 up out of the first one's plane.
  const Polygon3 hinge = {{-0.5, 3, -0.5}, {0.5, 3, -0.5}, {0.5, 3, 0.5}, {-0.5, 3.1, 0.5}};
  for (const Polygon3& corners : {dart, hinge}) {
    const ImportResult result = importText(objWithLamp(corners, {{0, 1, 2}, {0, 2, 3}}, false));
    EXPECT_EQ(result.report.repaired("coplanar_light_triangles_joined"), 0u) << result.report.summary();
    ASSERT_EQ(result.scene.lights().size(), 2u);
    for (const Light& light : result.scene.lights()) {
      EXPECT_EQ(light.polygon.size(), 3u);
      EXPECT_EQ(light.radiance, Vec3(5, 4, 3));
    }
  }
}

// A random triangulation of the convex polygon 0..n-1: split by a random diagonal, recurse.
void triangulate(std::vector<int> ring, std::mt19937_64& rng, std::vector<IndexPolygon>& out) {
  if (ring.size() == 3) {
    out.push_back({ring[0], ring[1], ring[2]});
    return;
  }
  const size_t n = ring.size();
  const size_t a = std::uniform_int_distribution<size_t>(0, n - 1)(rng);
  const size_t b = (a + std::uniform_int_distribution<size_t>(2, n - 2)(rng)) % n;
  std::vector<int> left, right;
  for (size_t k = a;; k = (k + 1) % n) {
    left.push_back(ring[k]);
    if (k == b) break;
  }
  for (size_t k = b;; k = (k + 1) % n) {
    right.push_back(ring[k]);
    if (k == a) break;
  }
  triangulate(left, rng, out);
  triangulate(right, rng, out);
}

TEST(LightJoin, SeededConvexPolygonsSplitAndShuffledComeBackAsOneLight) {
  for (uint64_t seed = 1; seed <= 60; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    // A plane through a point above the floor, facing down at some slant.
    const Vec3 normal = glm::normalize(Vec3(unit(rng) - 0.5, -0.6 - unit(rng), unit(rng) - 0.5));
    const Vec3 centre(unit(rng) - 0.5, 2.5 + unit(rng), unit(rng) - 0.5);
    const PlaneFrame frame = PlaneFrame::onPlane(Plane::throughPoint(normal, centre), centre);
    // Corners on an ellipse at increasing angles, never closer than a quarter of an even step.
    const int n = std::uniform_int_distribution<int>(3, 12)(rng);
    const double step = 2 * M_PI / n, ru = 0.2 + unit(rng), rv = 0.2 + unit(rng);
    Polygon3 corners;
    for (int k = 0; k < n; ++k) {
      const double angle = (k + 0.75 * unit(rng)) * step;
      corners.push_back(frame.to3D({ru * std::cos(angle), rv * std::sin(angle)}));
    }
    std::vector<int> ring;
    for (int k = 0; k < n; ++k) ring.push_back(k);
    std::vector<IndexPolygon> triangles;
    triangulate(ring, rng, triangles);
    std::shuffle(triangles.begin(), triangles.end(), rng);
    for (IndexPolygon& t : triangles) std::rotate(t.begin(), t.begin() + std::uniform_int_distribution<int>(0, 2)(rng), t.end());
    const bool ownCorners = seed % 2 == 0;

    const ImportResult result = importText(objWithLamp(corners, triangles, ownCorners));
    ASSERT_EQ(result.scene.lights().size(), 1u) << "seed " << seed << "\n" << result.report.summary();
    EXPECT_TRUE(sameCycle(result.scene.lights()[0].polygon, corners)) << "seed " << seed;
    EXPECT_EQ(result.scene.lights()[0].radiance, Vec3(5, 4, 3));
    EXPECT_EQ(result.report.repaired("coplanar_light_triangles_joined"), triangles.size() - 1) << "seed " << seed;
  }
}

TEST(LightJoin, SeededQuadsJoinIffConvexAndFlat) {
  size_t joined = 0, apart = 0;
  for (uint64_t seed = 1; seed <= 400; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> coordinate(-0.5, 0.5);
    // Triangles (p0 p1 p2) and (p0 p2 p3), p1 and p3 on either side of the diagonal p0 p2.
    Vec2 q[4];
    for (Vec2& p : q) p = {coordinate(rng), coordinate(rng)};
    const auto side = [](const Vec2& a, const Vec2& b, const Vec2& p) { return cross2(b - a, p - a); };
    if (side(q[0], q[2], q[1]) > 0) std::swap(q[1], q[3]);
    // Clear cases only: no corner within 0.02 of a line the decision turns on.
    const double s1 = side(q[0], q[2], q[1]), s3 = side(q[0], q[2], q[3]);
    const double t0 = side(q[3], q[1], q[0]), t2 = side(q[3], q[1], q[2]);
    if (std::min({-s1, s3, std::abs(t0), std::abs(t2)}) < 0.02) continue;
    const bool convex = t0 * t2 < 0;
    const bool flat = seed % 3 != 0;
    // In the plane y = 3 as (x, z) = (v, u): both triangles face up, and are turned down first.
    Polygon3 corners;
    for (const Vec2& p : q) corners.push_back({p.y, 3, p.x});
    if (!flat) corners[3].y += 0.05;
    const ImportResult result = importText(objWithLamp(corners, {{0, 1, 2}, {0, 2, 3}}, false));
    const size_t expected = convex && flat ? 1 : 2;
    ASSERT_EQ(result.scene.lights().size(), expected)
        << "seed " << seed << " convex " << convex << " flat " << flat << "\n" << result.report.summary();
    (expected == 1 ? joined : apart) += 1;
  }
  EXPECT_GT(joined, 20u);
  EXPECT_GT(apart, 20u);
}

}  // namespace
}  // namespace penumbra::interchange
