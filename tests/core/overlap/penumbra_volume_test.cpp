// PenumbraVolume against an independent membership test: x is in PSV(P) iff x is
// behind P and the cone from x over the light's front part meets P (clipping P
// by the cone's planes). Seeded random polygons and generated-scene faces.
#include "core/overlap/penumbra_volume.h"

#include <gtest/gtest.h>

#include <random>

#include "core/geom/clip.h"
#include "core/geom/plane_frame.h"
#include "overlap_test_support.h"
#include "scenegen/cubes_scene.h"

namespace penumbra {
namespace {

using overlap_test::samplePolygon;

enum class Truth { Inside, Outside, Unsure };

// Independent truth with a safety band `band`: Inside if x lies more than band
// behind P and the cone shrunk by band still meets P; Outside if x is more than
// band in front of P or the cone grown by band misses P; Unsure otherwise
// (near the boundary, or x too close to the light's plane for a proper cone).
Truth coneTruth(const Vec3& x, const Polygon3& face, const Plane& facePlane,
                const Polygon3& lightFront, double band) {
  const double dx = facePlane.signedDistance(x);
  if (dx > band) return Truth::Outside;
  const std::optional<Plane> lightPlane = planeOf(lightFront);
  if (!lightPlane) return Truth::Unsure;
  // Base plane oriented towards the apex; x must be clearly off the light's plane.
  Plane base = *lightPlane;
  if (base.signedDistance(x) < 0) base = base.flipped();
  if (base.signedDistance(x) <= 100 * band) return Truth::Unsure;
  const Vec3 inner = centroid(lightFront);
  std::vector<Plane> cone{base};
  for (size_t i = 0; i < lightFront.size(); ++i) {
    const Vec3& a = lightFront[i];
    const Vec3& b = lightFront[(i + 1) % lightFront.size()];
    const Vec3 n = glm::cross(b - a, x - a);
    if (glm::length(n) == 0) return Truth::Unsure;
    Plane side = Plane::throughPoint(glm::normalize(n), a);
    if (side.signedDistance(inner) < 0) side = side.flipped();
    cone.push_back(side);
  }
  auto meets = [&](double grow) {
    Polygon3 rest = face;
    for (Plane plane : cone) {
      plane.offset += grow;  // grow > 0 enlarges the kept (front) side
      rest = clipFront(rest, plane, 0.0);
      if (rest.empty()) return false;
    }
    return true;
  };
  if (!meets(band)) return Truth::Outside;
  if (dx < -band && meets(-band)) return Truth::Inside;
  return Truth::Unsure;
}

// A random convex polygon: a regular n-gon (3..6) of random size, orientation
// and position inside a box of half-size `spread`.
Polygon3 randomPolygon(std::mt19937_64& rng, double spread) {
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> corners(3, 6);
  Vec3 n{unit(rng), unit(rng), unit(rng)};
  while (glm::length(n) < 0.1) n = {unit(rng), unit(rng), unit(rng)};
  n = glm::normalize(n);
  const Vec3 centre{spread * unit(rng), spread * unit(rng), spread * unit(rng)};
  const PlaneFrame frame = PlaneFrame::onPlane(Plane::throughPoint(n, centre), centre);
  const double radius = 0.2 + 0.8 * (0.5 + 0.5 * unit(rng));
  const int count = corners(rng);
  const double phase = M_PI * unit(rng);
  Polygon3 polygon;
  for (int k = 0; k < count; ++k) {
    const double angle = phase + 2 * M_PI * k / count;
    polygon.push_back(frame.to3D(radius * Vec2{std::cos(angle), std::sin(angle)}));
  }
  return polygon;
}

struct Tally {
  int inside = 0, outside = 0, unsure = 0, segmentPoints = 0;
};

// Checks one (face, light) configuration; returns false if the face is back.
bool checkVolume(const Polygon3& face, const Polygon3& light, const Tolerance& tol,
                 std::mt19937_64& rng, Tally& tally) {
  const std::optional<Plane> facePlane = planeOf(face);
  if (!facePlane) return false;
  const std::optional<PenumbraVolume> volume = penumbraVolume(face, *facePlane, light, tol);
  const Polygon3 lightFront = clipFront(light, *facePlane, tol.length());
  EXPECT_EQ(volume.has_value(), lightFront.size() >= 3);
  if (!volume) return false;
  volume->validate();

  // Points on segments from the light's front part through P, beyond P.
  std::uniform_real_distribution<double> beyond(1.0, 4.0);
  for (int k = 0; k < 60; ++k) {
    const Vec3 s = samplePolygon(lightFront, rng);
    const Vec3 p = samplePolygon(face, rng);
    if (facePlane->signedDistance(s) <= tol.onPlane()) continue;  // not strictly in front
    const Vec3 x = s + beyond(rng) * (p - s);
    ++tally.segmentPoints;
    EXPECT_TRUE(volume->contains(x)) << "segment point outside PSV";
    const Vec3 onFace = s + (p - s);
    EXPECT_TRUE(volume->contains(onFace)) << "face point outside PSV";
  }

  // Random points around, and near the boundary, against the cone truth.
  Vec3 lo = face[0], hi = face[0];
  for (const Vec3& v : face) lo = glm::min(lo, v), hi = glm::max(hi, v);
  for (const Vec3& v : light) lo = glm::min(lo, v), hi = glm::max(hi, v);
  const Vec3 centre = 0.5 * (lo + hi), half = 2.0 * (hi - lo) + Vec3(tol.length());
  std::uniform_real_distribution<double> unit(-1, 1), logScale(-4, -1);
  const double band = 10 * tol.onPlane();
  for (int k = 0; k < 300; ++k) {
    Vec3 x = centre + Vec3{half.x * unit(rng), half.y * unit(rng), half.z * unit(rng)};
    if (k % 2 == 1) {
      // Near the boundary: a segment point pushed a random small distance.
      const Vec3 s = samplePolygon(lightFront, rng);
      const Vec3 p = samplePolygon(face, rng);
      const Vec3 dir = glm::normalize(Vec3{unit(rng), unit(rng), unit(rng)} + Vec3(1e-3));
      x = s + beyond(rng) * (p - s) + std::pow(10.0, logScale(rng)) * tol.sceneSize * dir;
    }
    switch (coneTruth(x, face, *facePlane, lightFront, band)) {
      case Truth::Inside:
        ++tally.inside;
        EXPECT_TRUE(volume->contains(x)) << "reachable point outside PSV";
        break;
      case Truth::Outside:
        ++tally.outside;
        EXPECT_FALSE(volume->contains(x)) << "unreachable point inside PSV";
        break;
      case Truth::Unsure:
        ++tally.unsure;
        break;
    }
  }
  return true;
}

TEST(PenumbraVolume, MatchesConeMembershipOnRandomPolygons) {
  std::mt19937_64 rng(20240611);
  const Tolerance tol = Tolerance::forSize(6.0);
  Tally tally;
  int configurations = 0, offending = 0;
  for (int k = 0; k < 400; ++k) {
    const Polygon3 light = randomPolygon(rng, 1.0);
    const Polygon3 face = randomPolygon(rng, 1.5);
    const std::optional<Plane> fp = planeOf(face);
    bool cut = false, front = false, back = false;
    for (const Vec3& v : light) {
      front |= fp->signedDistance(v) > tol.length();
      back |= fp->signedDistance(v) < -tol.length();
    }
    cut = front && back;
    if (checkVolume(face, light, tol, rng, tally)) {
      ++configurations;
      offending += cut;
    }
  }
  std::printf("random: %d configurations (%d offending), segment points %d, inside %d, outside %d, unsure %d\n",
              configurations, offending, tally.segmentPoints, tally.inside, tally.outside, tally.unsure);
  EXPECT_GT(offending, 50);
  EXPECT_GT(tally.inside, 1000);
  EXPECT_GT(tally.outside, 1000);
}

// The quick reject never rejects what clipInside keeps: on seeded random volumes (offending and
// not) and polygons, near them and touching their bounds within a few eps, outsideABound implies an
// empty clipInside at the tolerance's eps and at 0; and it does reject most far polygons.
TEST(PenumbraVolume, OutsideABoundOnlyRejectsWhatClipInsideEmpties) {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(-1, 1);
  const Tolerance tol = Tolerance::forSize(6.0);
  int rejected = 0, kept = 0, nearBound = 0;
  for (int k = 0; k < 300; ++k) {
    const Polygon3 light = randomPolygon(rng, 1.0);
    const Polygon3 face = randomPolygon(rng, 1.5);
    const std::optional<Plane> plane = planeOf(face);
    if (!plane) continue;
    const auto volume = penumbraVolume(face, *plane, light, tol, VolumeMargin::Tight);
    if (!volume) continue;
    for (int t = 0; t < 40; ++t) {
      Polygon3 polygon = randomPolygon(rng, 1.5);
      if (t % 4 == 0) {  // moved so one corner sits on a bound, within a few eps
        const Plane& bound = volume->bounds[size_t(rng() % volume->bounds.size())];
        const double shift = bound.signedDistance(polygon[0]) - 3 * tol.length() * u(rng);
        for (Vec3& p : polygon) p -= shift * bound.normal;
        ++nearBound;
      }
      if (!volume->outsideABound(polygon)) {
        ++kept;
        continue;
      }
      ++rejected;
      EXPECT_TRUE(volume->clipInside(polygon, tol.length()).empty()) << "volume " << k << " polygon " << t;
      EXPECT_TRUE(volume->clipInside(polygon, 0.0).empty()) << "volume " << k << " polygon " << t;
    }
  }
  EXPECT_GT(rejected, 2000);
  EXPECT_GT(kept, 1000);
  EXPECT_GT(nearBound, 1000);
}

TEST(PenumbraVolume, MatchesConeMembershipOnSceneFaces) {
  std::mt19937_64 rng(7);
  Tally tally;
  int faces = 0;
  for (uint64_t seed = 1; seed <= 8; ++seed) {
    CubesSceneOptions options;
    options.cubes = 6;
    options.seed = seed;
    options.tiltedLight = seed % 2 == 0;
    options.lightScale = seed % 3 == 0 ? 0.2 : 1.0;
    const Scene scene = makeCubesScene(options);
    for (const Face& face : scene.faces())
      faces += checkVolume(face.polygon, scene.lights()[0].polygon, scene.tolerance(), rng, tally);
  }
  std::printf("scenes: %d faces, inside %d, outside %d, unsure %d\n", faces, tally.inside,
              tally.outside, tally.unsure);
  EXPECT_GT(tally.inside, 1000);
  EXPECT_GT(tally.outside, 1000);
}

TEST(PenumbraVolume, BackFaceHasNone) {
  const Tolerance tol = Tolerance::forSize(4.0);
  const Polygon3 light{{-0.5, 3, -0.5}, {-0.5, 3, 0.5}, {0.5, 3, 0.5}, {0.5, 3, -0.5}};  // faces down
  auto facingDown = [](Polygon3 p) {
    if (newellVector(p).y > 0) std::reverse(p.begin(), p.end());
    return p;
  };
  const Polygon3 faceDown = facingDown({{-1, 1, -1}, {-1, 1, 1}, {1, 1, 1}, {1, 1, -1}});
  EXPECT_FALSE(penumbraVolume(faceDown, *planeOf(faceDown), light, tol).has_value());
  // A face in the light's own plane: the light lies on its plane, either way up.
  Polygon3 coplanar = facingDown({{1, 3, -0.5}, {1, 3, 0.5}, {2, 3, 0.5}, {2, 3, -0.5}});
  EXPECT_FALSE(penumbraVolume(coplanar, *planeOf(coplanar), light, tol).has_value());
  std::reverse(coplanar.begin(), coplanar.end());
  EXPECT_FALSE(penumbraVolume(coplanar, *planeOf(coplanar), light, tol).has_value());
}

TEST(PenumbraVolume, DegenerateInputsStayConservative) {
  const Tolerance tol = Tolerance::forSize(4.0);
  const Polygon3 light{{-0.5, 3, -0.5}, {-0.5, 3, 0.5}, {0.5, 3, 0.5}, {0.5, 3, -0.5}};
  // A vertical face whose plane contains a light edge (x = 0.5): the light
  // touches its plane along an edge; all of the light is in front (x < 0.5 side).
  const Polygon3 touching{{0.5, 0, -1}, {0.5, 2, -1}, {0.5, 2, 1}, {0.5, 0, 1}};
  const std::optional<Plane> tp = planeOf(touching);
  ASSERT_TRUE(tp);
  const Plane facing = glm::dot(tp->normal, Vec3(-1, 0, 0)) > 0 ? *tp : tp->flipped();
  Polygon3 oriented = touching;
  if (facing.normal != tp->normal) std::reverse(oriented.begin(), oriented.end());
  const std::optional<PenumbraVolume> volume = penumbraVolume(oriented, facing, light, tol);
  ASSERT_TRUE(volume);
  volume->validate();
  // Grazing rays through the face reach points just behind it.
  EXPECT_TRUE(volume->contains(Vec3(0.5, 1, 0)));
  EXPECT_TRUE(volume->contains(Vec3(0.5 + 1e-3, 0.5, 0)));
  // A face crossing the light's plane (offending and touching the light).
  const Polygon3 piercing{{0, 2, -0.2}, {0, 4, -0.2}, {0, 4, 0.2}, {0, 2, 0.2}};
  std::mt19937_64 rng(3);
  Tally tally;
  checkVolume(piercing, light, tol, rng, tally);
  checkVolume(oriented, light, tol, rng, tally);
  EXPECT_GT(tally.segmentPoints, 0);
  // A zero-length edge in the face (duplicate vertex) does not crash.
  const Polygon3 duplicate{{-1, 1, -1}, {1, 1, -1}, {1, 1, -1}, {1, 1, 1}, {-1, 1, 1}};
  const std::optional<Plane> dp = planeOf(duplicate);
  ASSERT_TRUE(dp);
  const std::optional<PenumbraVolume> dv = penumbraVolume(duplicate, *dp, light, tol);
  if (dv) dv->validate();
}

}  // namespace
}  // namespace penumbra
