// castShadow against independent truth: ExactReference on tiny scenes (regions),
// the generating elements (segments), closed forms (parallel squares).
#include "core/shadow/cast_shadow.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "scenegen/cubes_scene.h"
#include "tests/core/shadow/shadow_fixtures.h"

namespace penumbra {
namespace {

using testing::checkRegions;
using testing::checkSegments;
using testing::facing;
using testing::makeTiny;
using testing::squareLight;
using testing::Tiny;

constexpr int kSamples = 400;

std::optional<SingleShadow> cast(const Tiny& tiny) {
  return castShadow(tiny.scene, 0, tiny.occluder(), tiny.receiver(), tiny.frame());
}

// Region margin: 1e-4 of the scene, well above the on-plane rule (1e-6) under
// which the reference deliberately ignores a face.
double margin(const Tiny& tiny) { return 100 * tiny.scene.tolerance().onPlane(); }

void expectTruth(const Tiny& tiny, const std::string& label, uint64_t seed = 1) {
  const auto shadow = cast(tiny);
  std::mt19937_64 rng(seed);
  const auto counts = checkRegions(tiny, shadow, rng, kSamples, margin(tiny), label);
  EXPECT_EQ(counts.mismatches, 0) << label;
  std::printf("%s: judged %d penumbra, %d umbra, %d outside\n", label.c_str(), counts.penumbra,
              counts.umbra, counts.outside);
  if (shadow) {
    EXPECT_GT(counts.penumbra, 0) << label;
    EXPECT_GT(counts.outside, 0) << label;
    EXPECT_EQ(checkSegments(tiny, *shadow, rng, label), 0) << label;
  }
}

Polygon3 square(double y, double x0, double x1, double z0, double z1, const Vec3& front) {
  return facing({{x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}}, front);
}

// Whether polygon equals the axis square [-h, h]² in the frame (any start vertex).
void expectSquare(const Polygon2& polygon, const PlaneFrame& frame, double h, double eps,
                  const std::string& label) {
  ASSERT_EQ(polygon.size(), 4u) << label;
  for (const Vec2& p : polygon) {
    const Vec3 x = frame.to3D(p);
    EXPECT_NEAR(std::abs(x.x), h, eps) << label;
    EXPECT_NEAR(std::abs(x.z), h, eps) << label;
  }
  EXPECT_NEAR(signedArea(polygon), 4 * h * h, eps) << label;
}

struct KindCounts {
  int penumbra = 0, umbra = 0, internal = 0, contact = 0;
};
KindCounts countKinds(const SingleShadow& shadow) {
  KindCounts c;
  for (const auto& s : shadow.segments) switch (s.kind) {
      case SegmentKind::Penumbra: ++c.penumbra; break;
      case SegmentKind::Umbra: ++c.umbra; break;
      case SegmentKind::Internal: ++c.internal; break;
      case SegmentKind::Contact: ++c.contact; break;
    }
  return c;
}

// Light half-side l at height H, occluder half-side o at height h, floor y = 0.
// From the floor, the EE planes trace lines at ±(o·k ± l·(k−1)), k = H/(H−h):
// penumbra square half-width P = ok + l(k−1), umbra U = ok − l(k−1) when > 0.
// Each of the 8 lines carries 4 wedges (2 VE + 2 EV). On the penumbra lines all 4
// are distinct Penumbra segments; on an umbra line the two VE wedges each split
// into the umbra edge (identical, kept once) plus an internal piece equal to an EV
// wedge (kept once): 1 Umbra + 2 Internal per line. Without umbra the inner lines
// carry 4 distinct Internal segments each.
TEST(CastShadowParallelSquares, WithUmbraMatchesClosedForm) {
  const double H = 3, h = 1, l = 0.5, o = 0.5, k = H / (H - h);
  const Tiny tiny = makeTiny(squareLight({0, H, 0}, l, {0, -1, 0}), square(h, -o, o, -o, o, {0, 1, 0}),
                             square(0, -10, 10, -10, 10, {0, 1, 0}));
  const auto shadow = cast(tiny);
  ASSERT_TRUE(shadow);
  const double eps = 10 * tiny.scene.tolerance().length();
  expectSquare(shadow->penumbra, tiny.frame(), o * k + l * (k - 1), eps, "penumbra");
  expectSquare(shadow->umbra, tiny.frame(), o * k - l * (k - 1), eps, "umbra");
  const KindCounts c = countKinds(*shadow);
  EXPECT_EQ(c.penumbra, 16);
  EXPECT_EQ(c.umbra, 4);
  EXPECT_EQ(c.internal, 8);
  EXPECT_EQ(c.contact, 0);
  // Every segment on one of the expected lines.
  for (const auto& s : shadow->segments) {
    const Vec3 a = tiny.frame().to3D(s.a), b = tiny.frame().to3D(s.b);
    const double line = s.kind == SegmentKind::Penumbra ? o * k + l * (k - 1) : o * k - l * (k - 1);
    const bool alongX = std::abs(a.z - b.z) <= eps;
    EXPECT_NEAR(std::abs(alongX ? a.z : a.x), line, eps);
    EXPECT_NEAR(std::abs(alongX ? b.z : b.x), line, eps);
  }
  expectTruth(tiny, "parallel squares with umbra");
}

TEST(CastShadowParallelSquares, WithoutUmbraMatchesClosedForm) {
  const double H = 3, h = 1.5, l = 1, o = 0.2, k = H / (H - h);
  const Tiny tiny = makeTiny(squareLight({0, H, 0}, l, {0, -1, 0}), square(h, -o, o, -o, o, {0, 1, 0}),
                             square(0, -10, 10, -10, 10, {0, 1, 0}));
  const auto shadow = cast(tiny);
  ASSERT_TRUE(shadow);
  const double eps = 10 * tiny.scene.tolerance().length();
  expectSquare(shadow->penumbra, tiny.frame(), o * k + l * (k - 1), eps, "penumbra");
  EXPECT_TRUE(shadow->umbra.empty());
  const KindCounts c = countKinds(*shadow);
  EXPECT_EQ(c.penumbra, 16);
  EXPECT_EQ(c.umbra, 0);
  EXPECT_EQ(c.internal, 16);
  for (const auto& s : shadow->segments) {
    if (s.kind != SegmentKind::Internal) continue;
    const Vec3 a = tiny.frame().to3D(s.a), b = tiny.frame().to3D(s.b);
    const bool alongX = std::abs(a.z - b.z) <= eps;
    EXPECT_NEAR(std::abs(alongX ? a.z : a.x), l * (k - 1) - o * k, eps);
  }
  expectTruth(tiny, "parallel squares without umbra");
}

TEST(CastShadowHandMade, CubeSideTouchingFloorGivesContact) {
  // The +x side of the unit cube [0,1]³ on the floor, lit from x ≈ 2.5.
  const Polygon3 side = facing({{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}, {1, 0, 0});
  const Tiny tiny = makeTiny(squareLight({2.5, 3, 0.5}, 0.5, {0, -1, 0}), side,
                             square(0, -5, 5, -5, 5, {0, 1, 0}));
  const auto shadow = cast(tiny);
  ASSERT_TRUE(shadow);
  const double eps = 10 * tiny.scene.tolerance().length();
  int contacts = 0;
  for (const auto& s : shadow->segments) {
    if (s.kind != SegmentKind::Contact) continue;
    ++contacts;
    const Vec3 a = tiny.frame().to3D(s.a), b = tiny.frame().to3D(s.b);
    EXPECT_NEAR(a.x, 1, eps);
    EXPECT_NEAR(b.x, 1, eps);
    EXPECT_NEAR(std::min(a.z, b.z), 0, eps);
    EXPECT_NEAR(std::max(a.z, b.z), 1, eps);
  }
  EXPECT_EQ(contacts, 1);
  EXPECT_FALSE(shadow->umbra.empty());  // right behind the foot of the face
  expectTruth(tiny, "cube side on floor");
}

TEST(CastShadowHandMade, OccluderPiercingFloorGivesContactAtTheCut) {
  // A slanted quad through the floor, cut at x = 0.25.
  const Polygon3 slab = facing({{0, -0.5, 0}, {0, -0.5, 1}, {1, 1.5, 1}, {1, 1.5, 0}}, {1, -0.5, 0});
  const Tiny tiny = makeTiny(squareLight({2.5, 3, 0.5}, 0.5, {0, -1, 0}), slab,
                             square(0, -5, 5, -5, 5, {0, 1, 0}));
  const auto shadow = cast(tiny);
  ASSERT_TRUE(shadow);
  const double eps = 10 * tiny.scene.tolerance().length();
  int contacts = 0;
  for (const auto& s : shadow->segments)
    if (s.kind == SegmentKind::Contact) {
      ++contacts;
      EXPECT_NEAR(tiny.frame().to3D(s.a).x, 0.25, eps);
      EXPECT_NEAR(tiny.frame().to3D(s.b).x, 0.25, eps);
    }
  EXPECT_EQ(contacts, 1);
  expectTruth(tiny, "piercing slab");
}

TEST(CastShadowHandMade, TiltedLight) {
  Light light = squareLight({0.3, 3, -0.2}, 0.6, {0.4, -1, 0.25});
  const Tiny tiny = makeTiny(light, square(1.2, -0.4, 0.5, -0.3, 0.3, {0, 1, 0}),
                             square(0, -6, 6, -6, 6, {0, 1, 0}));
  ASSERT_TRUE(cast(tiny));
  expectTruth(tiny, "tilted light");
}

TEST(CastShadowHandMade, WallNextToCeilingLightHasUnboundedShadow) {
  // Light x ∈ [-1, 1] at y = 3; occluder x ∈ [0.5, 1.5] at y = 2.5, partly farther
  // from the wall x = 2 than the light's near vertices: rays from those vertices
  // through its far part never reach the wall (the shadow on the plane is unbounded).
  const Polygon3 wall = facing({{2, 0, -3}, {2, 3, -3}, {2, 3, 3}, {2, 0, 3}}, {-1, 0, 0});
  const Tiny tiny = makeTiny(squareLight({0, 3, 0}, 1, {0, -1, 0}), square(2.5, 0.5, 1.5, -0.5, 0.5, {0, 1, 0}),
                             wall);
  const auto shadow = cast(tiny);
  ASSERT_TRUE(shadow);
  expectTruth(tiny, "wall receiver");
}

TEST(CastShadowHandMade, RejectsReceiverInFrontOfOccluder) {
  const Tiny tiny = makeTiny(squareLight({0, 3, 0}, 0.5, {0, -1, 0}), square(1, -0.5, 0.5, -0.5, 0.5, {0, 1, 0}),
                             square(2, -5, 5, -5, 5, {0, 1, 0}));
  EXPECT_FALSE(cast(tiny));
  expectTruth(tiny, "receiver above occluder");
}

// Random (light, occluder, receiver) triples from generated rooms.
TEST(CastShadowRandom, RegionsAndSegmentsMatchReference) {
  int withShadow = 0, withoutShadow = 0, judged = 0, segments = 0, umbraPoints = 0, contacts = 0;
  int mismatches = 0, segmentFailures = 0;
  for (uint64_t seed = 1; seed <= 12 && (withShadow < 150 || withoutShadow < 30); ++seed) {
    CubesSceneOptions options;
    options.cubes = 5;
    options.seed = seed;
    options.tiltedLight = seed % 3 == 0;
    options.thinTables = seed % 2 ? 0.3 : 0.0;
    options.lightScale = seed % 4 == 1 ? 0.4 : 1.0;
    const Scene scene = makeCubesScene(options);
    const Light& light = scene.lights()[0];
    std::vector<std::pair<size_t, size_t>> pairs;
    const auto& faces = scene.faces();
    for (size_t o = 0; o < faces.size(); ++o) {
      if (scene.classify(faces[o], light) == FaceClass::Back) continue;
      for (size_t r = 0; r < faces.size(); ++r) {
        if (r == o || !scene.receivesLight(faces[r])) continue;
        const bool behind = std::any_of(faces[r].polygon.begin(), faces[r].polygon.end(), [&](const Vec3& p) {
          return faces[o].plane.signedDistance(p) < -scene.tolerance().onPlane();
        });
        if (behind) pairs.emplace_back(o, r);
      }
    }
    std::mt19937_64 rng(seed);
    std::shuffle(pairs.begin(), pairs.end(), rng);
    int perSceneWith = 0, perSceneWithout = 0;
    for (const auto& [o, r] : pairs) {
      const Tiny tiny = makeTiny(light, faces[o].polygon, faces[r].polygon);
      const auto shadow = cast(tiny);
      if (shadow ? perSceneWith >= 16 : perSceneWithout >= 4) continue;
      const std::string label = "seed " + std::to_string(seed) + " occluder " + std::to_string(o) +
                                " receiver " + std::to_string(r);
      const auto counts = checkRegions(tiny, shadow, rng, shadow ? 300 : 60, margin(tiny), label);
      mismatches += counts.mismatches;
      judged += counts.penumbra + counts.umbra + counts.outside;
      umbraPoints += counts.umbra;
      if (shadow) {
        ++perSceneWith;
        ++withShadow;
        segments += int(shadow->segments.size());
        contacts += countKinds(*shadow).contact;
        segmentFailures += checkSegments(tiny, *shadow, rng, label);
      } else {
        ++perSceneWithout;
        ++withoutShadow;
      }
    }
  }
  RecordProperty("configurations_with_shadow", withShadow);
  RecordProperty("configurations_without_shadow", withoutShadow);
  RecordProperty("judged_points", judged);
  RecordProperty("segments", segments);
  std::printf("random: %d with shadow, %d without, %d points judged (%d in umbra), %d segments (%d contact)\n",
              withShadow, withoutShadow, judged, umbraPoints, segments, contacts);
  EXPECT_GE(withShadow, 100);
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(segmentFailures, 0);
}

}  // namespace
}  // namespace penumbra
