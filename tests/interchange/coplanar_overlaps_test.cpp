// Coplanar overlapping faces: found iff they share a region of positive area in one
// plane (seeded: rectangles on an integer grid, turned into a random plane, against
// exact integer overlaps); on import a covered face facing the same way is dropped
// and every other overlap is kept, counted and named in a warning.
#include "interchange/coplanar_overlaps.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <tuple>

#include "interchange/obj_import.h"

namespace penumbra::interchange {
namespace {

// A rectangle [x0, x1] × [y0, y1] on the plane z = level of a frame, facing +z or -z.
struct Rect {
  int x0, y0, x1, y1, level;
  bool up;
};

Polygon3 placed(const Rect& r, const Mat3& rotation, const Vec3& shift) {
  Polygon3 corners;
  for (const auto& [x, y] : {std::pair{r.x0, r.y0}, {r.x1, r.y0}, {r.x1, r.y1}, {r.x0, r.y1}})
    corners.push_back(rotation * Vec3(x, y, r.level) + shift);
  if (!r.up) std::reverse(corners.begin(), corners.end());
  return corners;
}

int overlapArea(const Rect& a, const Rect& b) {
  const int w = std::min(a.x1, b.x1) - std::max(a.x0, b.x0),
            h = std::min(a.y1, b.y1) - std::max(a.y0, b.y0);
  return a.level == b.level && w > 0 && h > 0 ? w * h : 0;
}

bool inside(const Rect& a, const Rect& b) {
  return a.x0 >= b.x0 && a.x1 <= b.x1 && a.y0 >= b.y0 && a.y1 <= b.y1;
}

Mat3 randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> gauss;
  const Vec3 axis = glm::normalize(Vec3(gauss(rng), gauss(rng), gauss(rng)));
  const double angle = std::uniform_real_distribution<double>(0, 2 * M_PI)(rng);
  const double c = std::cos(angle), s = std::sin(angle);
  const Mat3 k(0, axis.z, -axis.y, -axis.z, 0, axis.x, axis.y, -axis.x,
               0);                             // column-major cross matrix
  return Mat3(1.0) + s * k + (1 - c) * k * k;  // Rodrigues
}

TEST(CoplanarOverlaps, SeededGridRectanglesAreFoundIffTheyShareArea) {
  size_t pairs = 0, covered = 0, touching = 0;
  for (uint64_t seed = 1; seed <= 150; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<int> coordinate(0, 8), size(1, 4), level(0, 1), coin(0, 1);
    const int count = std::uniform_int_distribution<int>(2, 14)(rng);
    std::vector<Rect> rects;
    std::vector<std::vector<Polygon3>> groups(3);
    std::vector<FaceRef> refs;
    const Mat3 rotation = randomRotation(rng);
    const Vec3 shift(coordinate(rng) * 0.37, -coordinate(rng) * 1.3, coordinate(rng) * 0.11);
    for (int k = 0; k < count; ++k) {
      Rect r;
      r.x0 = coordinate(rng);
      r.y0 = coordinate(rng);
      r.x1 = r.x0 + size(rng);
      r.y1 = r.y0 + size(rng);
      r.level = level(rng);
      r.up = coin(rng);
      rects.push_back(r);
      const size_t g = size_t(k % 3);
      refs.push_back({g, groups[g].size()});
      groups[g].push_back(placed(r, rotation, shift));
    }
    const std::vector<CoplanarOverlap> found = findCoplanarOverlaps(groups, Tolerance::forSize(16));

    // What integer arithmetic says, pair by pair (a before b as FaceRefs).
    std::set<std::tuple<FaceRef, FaceRef>> expected;
    for (size_t i = 0; i < rects.size(); ++i)
      for (size_t j = 0; j < rects.size(); ++j) {
        if (!(refs[i] < refs[j])) continue;
        if (overlapArea(rects[i], rects[j]) > 0)
          expected.insert({refs[i], refs[j]});
        else if (rects[i].level == rects[j].level &&
                 overlapArea(rects[i], {rects[j].x0 - 1, rects[j].y0 - 1, rects[j].x1 + 1,
                                        rects[j].y1 + 1, rects[j].level, true}) > 0)
          ++touching;  // apart or meeting along an edge or a corner: not an overlap
      }
    std::set<std::tuple<FaceRef, FaceRef>> got;
    for (const CoplanarOverlap& o : found) {
      ASSERT_TRUE(o.a < o.b);
      got.insert({o.a, o.b});
      const size_t i = size_t(std::find(refs.begin(), refs.end(), o.a) - refs.begin());
      const size_t j = size_t(std::find(refs.begin(), refs.end(), o.b) - refs.begin());
      const Rect &a = rects[i], &b = rects[j];
      EXPECT_NEAR(o.area, overlapArea(a, b), 1e-9) << "seed " << seed;
      EXPECT_EQ(o.backToBack, a.up != b.up) << "seed " << seed;
      std::optional<FaceRef> cover;
      if (a.up == b.up && inside(b, a))
        cover = o.b;
      else if (a.up == b.up && inside(a, b))
        cover = o.a;
      EXPECT_EQ(o.covered, cover) << "seed " << seed << " pair " << i << ", " << j;
      covered += cover.has_value();
    }
    EXPECT_EQ(got, expected) << "seed " << seed;
    pairs += expected.size();
  }
  // The cases occurred: overlaps, covers, and neighbours that only touch.
  EXPECT_GT(pairs, 200u);
  EXPECT_GT(covered, 20u);
  EXPECT_GT(touching, 100u);
}

TEST(CoplanarOverlaps, OnlyWithinTheOnPlaneDistance) {
  const Tolerance tolerance = Tolerance::forSize(10);
  const Polygon3 square = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
  for (double lift : {0.5 * tolerance.onPlane(), 2 * tolerance.onPlane()}) {
    const Polygon3 shifted = {{1, 1, lift}, {3, 1, lift}, {3, 3, lift}, {1, 3, lift}};
    const auto found = findCoplanarOverlaps({{square}, {shifted}}, tolerance);
    EXPECT_EQ(found.size(), lift < tolerance.onPlane() ? 1u : 0u) << "lift " << lift;
  }
  // A face and its exact reverse in one group: a two-sided sheet, already counted as such.
  const Polygon3 reversed(square.rbegin(), square.rend());
  EXPECT_TRUE(findCoplanarOverlaps({{square, reversed}}, tolerance).empty());
  EXPECT_EQ(findCoplanarOverlaps({{square}, {reversed}}, tolerance).size(), 1u);
}

TEST(CoplanarOverlaps, DecisionDropsCoveredFacesAndKeepsTheRest) {
  // a ⊇ b ≡ c (b, c equal), d partly over a.
  const FaceRef a{0, 0}, b{1, 0}, c{2, 0}, d{3, 0};
  const std::vector<CoplanarOverlap> found = {{a, b, false, 1, b},
                                              {a, c, false, 1, c},
                                              {a, d, false, 0.5, std::nullopt},
                                              {b, c, false, 1, c}};
  const CoplanarDecision decision = decideCoplanarOverlaps(found);
  EXPECT_EQ(decision.dropped, (std::map<FaceRef, FaceRef>{{b, a}, {c, a}}));
  ASSERT_EQ(decision.kept.size(), 1u);
  EXPECT_EQ(decision.kept[0].b, d);
}

// Imports: a floor, a lamp above, and `extra` objects.
ImportResult importWith(const std::string& extra) {
  const std::string obj =
      "mtllib m.mtl\no floor\nusemtl grey\nv -2 0 -2\nv -2 0 2\nv 2 0 2\nv 2 0 -2\nf 1 2 3 4\n" +
      extra +
      "o lamp\nusemtl lamp\nv -0.5 3 -0.5\nv 0.5 3 -0.5\nv 0.5 3 0.5\nv -0.5 3 0.5\n"
      "f -4 -3 -2 -1\n";
  return importObjText(obj, {{"m.mtl", "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKe 5 5 5\n"}}, {},
                       "overlap.obj");
}

bool anyWarningHas(const ImportReport& report, const std::string& text) {
  return std::any_of(report.warnings.begin(), report.warnings.end(),
                     [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

TEST(CoplanarOverlaps, ImportDropsACoveredDecalAndNamesIt) {
  // A rug on the floor facing up, wholly within it.
  const ImportResult result = importWith(
      "o rug\nusemtl grey\nv -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\nf -4 -3 -2 -1\n"
      "o mat\nusemtl grey\nv 1.5 0 1.5\nv 1.5 0 3\nv 3 0 3\nv 3 0 1.5\nf -4 -3 -2 -1\n");
  const ImportReport& report = result.report;
  EXPECT_EQ(report.repaired("covered_coplanar_faces_dropped"), 1u) << report.summary();
  EXPECT_TRUE(
      anyWarningHas(report, "a face of 'rug' around (0, 0, 0) lies wholly within 'floor' face 0"))
      << report.summary();
  EXPECT_FALSE(result.scene.findObject("rug"));  // its only face went
  EXPECT_EQ(report.repaired("groups_emptied_by_repairs"), 1u);
  // The mat sticks out past the floor's corner: kept, and reported.
  EXPECT_EQ(report.repaired("coplanar_overlapping_face_pairs"), 1u);
  EXPECT_TRUE(anyWarningHas(
      report,
      "'floor' face 0 and 'mat' face 0 lie in one plane facing the same way and share "
      "an area of 0.25; both kept"))
      << report.summary();
  EXPECT_TRUE(result.scene.findObject("mat"));
}

TEST(CoplanarOverlaps, ImportKeepsABoxBottomOnTheFloorAndSaysSo) {
  // A unit box standing on the floor: its bottom faces down, back to back with the floor.
  const ImportResult result = importWith(
      "o box\nusemtl grey\nv 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nv 0 1 0\nv 1 1 0\nv 1 1 1\nv 0 1 1\n"
      "f -8 -7 -6 -5\nf -4 -1 -2 -3\nf -8 -4 -3 -7\nf -7 -3 -2 -6\nf -6 -2 -1 -5\nf -5 -1 -4 -8\n");
  const ImportReport& report = result.report;
  EXPECT_EQ(report.repaired("covered_coplanar_faces_dropped"), 0u) << report.summary();
  EXPECT_EQ(report.repaired("coplanar_overlapping_face_pairs"), 1u);
  EXPECT_TRUE(
      anyWarningHas(report,
                    "'floor' face 0 and 'box' face 0 lie in one plane back to back and share an "
                    "area of 1; both kept"))
      << report.summary();
  EXPECT_EQ(result.scene.objects()[*result.scene.findObject("box")].faces.size(), 6u);
}

TEST(CoplanarOverlaps, FacesMeetingAlongAnEdgeAreNotReported) {
  // Two tiles sharing an edge, and one meeting the floor's edge from outside.
  const ImportResult result = importWith(
      "o tiles\nusemtl grey\nv 2 0 -2\nv 2 0 0\nv 3 0 0\nv 3 0 -2\nv 3 0 2\nv 2 0 2\n"
      "f -6 -5 -4 -3\nf -5 -1 -2 -4\n");
  EXPECT_EQ(result.report.repaired("coplanar_overlapping_face_pairs"), 0u)
      << result.report.summary();
  EXPECT_EQ(result.report.repaired("covered_coplanar_faces_dropped"), 0u);
  EXPECT_TRUE(result.report.warnings.empty()) << result.report.summary();
}

}  // namespace
}  // namespace penumbra::interchange
