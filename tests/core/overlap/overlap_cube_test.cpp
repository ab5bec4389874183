// OverlapCube: no shadow relation is missed (ray-sampled blocker pairs, plus an
// exact double-precision check of every sampled segment against the faces the
// cube rules out), validate() after every operation, insert/remove round trips,
// the grid rule and selectivity. Seeded generated scenes throughout.
#include "core/overlap/overlap_cube.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <random>
#include <set>

#include "core/geom/clip.h"
#include "core/raycast/ray_scene.h"
#include "core/reference/exact_irradiance.h"
#include "overlap_test_support.h"
#include "scenegen/cubes_scene.h"

namespace penumbra {
namespace {

using overlap_test::blocksExactly;
using overlap_test::samplePolygon;
using FacePair = std::pair<FaceId, FaceId>;

FacePair orderedPair(FaceId a, FaceId b) { return a < b ? FacePair{a, b} : FacePair{b, a}; }

struct RelationStats {
  size_t candidatePairs = 0, truePairs = 0, segments = 0, exactChecks = 0, shadedPoints = 0;
};

// The defining property for one light: every (blocker, receiver) pair found by
// sampling segments p→q (p on the receiver, q on the part of the light strictly
// in front of it) is a candidate pair, and no face outside candidates(R) blocks
// any sampled segment by the exact rule either.
void checkNoMissedRelations(const Scene& scene, size_t light, const OverlapCube& cube,
                            const RayScene& rays, int samplesPerFace, std::mt19937_64& rng,
                            RelationStats& stats) {
  const std::vector<FacePair> pairs = cube.candidatePairs();
  const std::set<FacePair> candidateSet(pairs.begin(), pairs.end());
  ASSERT_EQ(candidateSet.size(), pairs.size()) << "candidatePairs repeats a pair";
  std::set<FacePair> truePairs;
  const std::vector<Face>& faces = scene.faces();
  const Tolerance tol = scene.tolerance();
  const ExactReference reference(scene);

  for (const Face& receiver : faces) {
    if (!cube.holds(receiver.id)) continue;  // back for this light
    const Polygon3 lightFront = clipFront(scene.lights()[light].polygon, receiver.plane, tol.length());
    ASSERT_GE(lightFront.size(), 3u);
    const std::vector<FaceId> candidates = cube.candidates(receiver.id);
    std::vector<const Face*> ruledOut;
    for (const Face& f : faces)
      if (f.id != receiver.id && !std::binary_search(candidates.begin(), candidates.end(), f.id))
        ruledOut.push_back(&f);

    for (int k = 0; k < samplesPerFace; ++k) {
      const Vec3 p = samplePolygon(receiver.polygon, rng);
      const Vec3 q = samplePolygon(lightFront, rng);
      if (receiver.plane.signedDistance(q) <= tol.onPlane()) continue;
      ++stats.segments;
      for (const uint32_t b : rays.blockers(p, q)) {
        const FacePair pair = orderedPair(faces[b].id, receiver.id);
        truePairs.insert(pair);
        EXPECT_TRUE(candidateSet.count(pair))
            << "missed: blocker (" << faces[b].id.object << "," << faces[b].id.face << ") receiver ("
            << receiver.id.object << "," << receiver.id.face << ") light " << light;
      }
      for (const Face* f : ruledOut) {
        ++stats.exactChecks;
        EXPECT_FALSE(blocksExactly(*f, p, q, tol.onPlane()))
            << "ruled-out face (" << f->id.object << "," << f->id.face << ") blocks receiver ("
            << receiver.id.object << "," << receiver.id.face << ")";
      }
    }
    // The exact reference: a point that does not see all of the light's front
    // part is shaded by some face, so the receiver has candidates.
    for (int k = 0; k < 4; ++k) {
      const Vec3 p = samplePolygon(receiver.polygon, rng);
      const LightVisibility v = reference.visibility(p, receiver.plane.normal, light);
      if (v.lightClass == LightClass::Lit) continue;
      ++stats.shadedPoints;
      EXPECT_FALSE(candidates.empty()) << "shaded point on a receiver without candidates";
    }
  }
  stats.candidatePairs += pairs.size();
  stats.truePairs += truePairs.size();
}

CubesSceneOptions variedOptions(uint64_t seed) {
  CubesSceneOptions o;
  o.seed = seed;
  o.cubes = 3 + static_cast<int>(seed % 10);
  o.stackedFraction = seed % 4 == 0 ? 0.5 : 0.2;
  o.thinTables = seed % 5 == 0 ? 0.4 : 0.0;
  o.tiltedLight = seed % 3 == 0;
  o.twoLights = seed % 7 == 0;
  if (o.twoLights) o.cubes = std::max(o.cubes, 8);  // room wide enough for two lights
  o.lightScale = seed % 6 == 0 ? 0.2 : 1.0;
  return o;
}

TEST(OverlapCube, NeverMissesAShadowRelation) {
  std::mt19937_64 rng(99);
  RelationStats stats;
  int scenes = 0, cubes = 0;
  for (uint64_t seed = 1; seed <= 50; ++seed) {
    const Scene scene = makeCubesScene(variedOptions(seed));
    const RayScene rays(scene);
    ++scenes;
    for (size_t light = 0; light < scene.lights().size(); ++light) {
      const OverlapCube cube(scene, light);
      cube.validate();
      ++cubes;
      checkNoMissedRelations(scene, light, cube, rays, 400, rng, stats);
    }
  }
  std::printf("%d scenes, %d cubes: %zu candidate pairs, %zu true pairs (ratio %.2f); %zu segments, "
              "%zu exact checks, %zu shaded reference points\n",
              scenes, cubes, stats.candidatePairs, stats.truePairs,
              double(stats.candidatePairs) / std::max<size_t>(1, stats.truePairs), stats.segments,
              stats.exactChecks, stats.shadedPoints);
  EXPECT_GT(stats.truePairs, 500u);  // the sampling really finds shadows
  EXPECT_GT(stats.shadedPoints, 100u);
}

// Snapshot of every list, to compare structures built in different orders.
struct Snapshot {
  std::map<FaceId, std::vector<TileId>> tilesOfFace;
  std::map<uint32_t, std::vector<FaceId>> facesOfTile;
  bool operator==(const Snapshot&) const = default;
};

Snapshot snapshot(const OverlapCube& cube) {
  Snapshot s;
  for (const FaceId f : cube.heldFaces()) s.tilesOfFace[f] = cube.tilesOf(f);
  for (uint32_t t = 0; t < cube.tileCount(); ++t) {
    std::vector<FaceId> in = cube.facesIn(TileId{t});
    if (!in.empty()) s.facesOfTile[t] = std::move(in);
  }
  return s;
}

TEST(OverlapCube, RemoveAndReinsertRoundTrips) {
  std::mt19937_64 rng(5);
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    const Scene scene = makeCubesScene(variedOptions(seed + 100));
    OverlapCube cube(scene, 0, OverlapCubeSettings{16, std::nullopt});
    cube.validate();
    const Snapshot before = snapshot(cube);
    const std::vector<FacePair> pairsBefore = cube.candidatePairs();

    // Remove a random half of the faces, one at a time, then put them back in
    // another order; and whole objects, as an edit does.
    std::vector<const Face*> faces;
    for (const Face& f : scene.faces()) faces.push_back(&f);
    std::shuffle(faces.begin(), faces.end(), rng);
    faces.resize(faces.size() / 2);
    std::vector<const Face*> removed;
    for (const Face* f : faces) {
      const bool held = cube.holds(f->id);
      EXPECT_EQ(cube.removeFace(f->id), held);
      EXPECT_FALSE(cube.holds(f->id));
      EXPECT_FALSE(cube.removeFace(f->id));  // second removal is a no-op
      cube.validate();
      if (held) removed.push_back(f);
      for (const FaceId other : cube.candidates(faces.front()->id)) EXPECT_TRUE(cube.holds(other));
    }
    EXPECT_LT(cube.counters().faces, before.tilesOfFace.size() + 1);
    std::shuffle(removed.begin(), removed.end(), rng);
    for (const Face* f : removed) {
      EXPECT_TRUE(cube.insertFace(*f));
      cube.validate();
      EXPECT_THROW(cube.insertFace(*f), std::invalid_argument);
      cube.validate();
    }
    EXPECT_EQ(snapshot(cube), before);
    EXPECT_EQ(cube.candidatePairs(), pairsBefore);

    const uint32_t object = static_cast<uint32_t>(scene.objects().size() - 1);
    for (const Face& f : scene.faces()) {
      if (f.id.object != object) continue;
      cube.removeFace(f.id);
      cube.validate();
    }
    for (const Face& f : scene.faces()) {
      if (f.id.object != object) continue;
      cube.insertFace(f);
      cube.validate();
    }
    EXPECT_EQ(snapshot(cube), before);
  }
}

TEST(OverlapCube, BackFacesAreNotHeld) {
  const Scene scene = makeCubesScene(variedOptions(3));
  const OverlapCube cube(scene, 0);
  size_t expected = 0;
  for (const Face& f : scene.faces()) {
    const bool back = scene.classify(f, scene.lights()[0]) == FaceClass::Back;
    EXPECT_EQ(cube.holds(f.id), !back);
    expected += !back;
  }
  EXPECT_EQ(cube.counters().faces, expected);
  EXPECT_TRUE(cube.candidates(FaceId{9999, 0}).empty());
  EXPECT_THROW(OverlapCube(scene, 5), std::invalid_argument);
}

TEST(OverlapCube, GridRuleFollowsFaceCount) {
  int previous = 0;
  for (size_t n : {0, 1, 10, 64, 100, 500, 1000, 5000, 10000, 100000, 1000000}) {
    const int g = OverlapCube::gridForFaceCount(n);
    EXPECT_GE(g, OverlapCube::kMinGrid);
    EXPECT_LE(g, OverlapCube::kMaxGrid);
    EXPECT_GE(g, previous);
    previous = g;
  }
  EXPECT_LT(OverlapCube::gridForFaceCount(100), OverlapCube::gridForFaceCount(10000));
  const Scene scene = makeCubesScene(variedOptions(12));
  const OverlapCube cube(scene, 0);
  EXPECT_EQ(cube.grid(), OverlapCube::gridForFaceCount(scene.faces().size()));
  EXPECT_EQ(cube.tileCount(), 6u * cube.grid() * cube.grid());
  const OverlapCubeCounters c = cube.counters();
  EXPECT_EQ(c.tiles, cube.tileCount());
  EXPECT_GT(c.occupiedTiles, 0u);
  EXPECT_NEAR(c.meanTilesPerFace, double(c.tileEntries) / c.faces, 1e-12);
}

TEST(OverlapCube, CandidatesShrinkAsTheGridGrows) {
  for (uint64_t seed : {2, 9, 14}) {
    const Scene scene = makeCubesScene(variedOptions(seed));
    std::vector<FacePair> coarser;
    std::vector<size_t> counts;
    for (int g = 2; g <= 64; g *= 2) {
      const OverlapCube cube(scene, 0, OverlapCubeSettings{g, std::nullopt});
      cube.validate();
      const std::vector<FacePair> pairs = cube.candidatePairs();
      // Tiles of 2G nest in tiles of G: a finer grid can only drop pairs.
      if (!coarser.empty()) {
        EXPECT_TRUE(std::includes(coarser.begin(), coarser.end(), pairs.begin(), pairs.end()));
      }
      coarser = pairs;
      counts.push_back(pairs.size());
    }
    std::printf("seed %d: candidate pairs for G = 2..64:", int(seed));
    for (size_t c : counts) std::printf(" %zu", c);
    std::printf("\n");
    EXPECT_LT(counts.back(), counts.front());
  }
}

// ---- Targeted scenes ----------------------------------------------------------

Object quad(const std::string& id, Polygon3 corners, const Vec3& front) {
  if (glm::dot(newellVector(corners), front) < 0) std::reverse(corners.begin(), corners.end());
  Object o;
  o.id = id;
  o.vertices = corners;
  o.faces = {{0, 1, 2, 3}};
  return o;
}

Polygon3 horizontal(double x0, double x1, double z0, double z1, double y) {
  return {{x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}};
}

TEST(OverlapCube, TargetedRelations) {
  Light light;
  light.id = "light";
  light.polygon = horizontal(-0.1, 0.1, -0.1, 0.1, 3);
  if (glm::dot(newellVector(light.polygon), Vec3(0, -1, 0)) < 0)
    std::reverse(light.polygon.begin(), light.polygon.end());
  light.radiance = Vec3(1);
  std::vector<Object> objects{
      quad("left", horizontal(-2.5, -1.5, -0.5, 0.5, 0), Vec3(0, 1, 0)),      // 0
      quad("right", horizontal(1.5, 2.5, -0.5, 0.5, 0), Vec3(0, 1, 0)),       // 1
      quad("blocker", horizontal(1.2, 1.5, -0.2, 0.2, 1), Vec3(0, 1, 0)),     // 2: shades "right"
      quad("under", horizontal(1.2, 1.5, -0.2, 0.2, 0.99), Vec3(0, -1, 0)),   // 3: back face
      quad("wall", {{0, 2, -0.3}, {0, 4, -0.3}, {0, 4, 0.3}, {0, 2, 0.3}}, Vec3(1, 0, 0)),  // 4: pierces the light
  };
  const Scene scene({light}, {}, objects);
  const RayScene rays(scene);
  ASSERT_TRUE(rays.occluded(Vec3(2, 0, 0), Vec3(0, 3, 0)));  // the blocker does shade "right"
  for (int g : {0, 4, 32, 128}) {
    const OverlapCube cube(scene, 0, OverlapCubeSettings{g, std::nullopt});
    cube.validate();
    const FaceId left{0, 0}, right{1, 0}, blocker{2, 0}, under{3, 0}, wall{4, 0};
    EXPECT_TRUE(cube.holds(wall)) << "offending faces are held";
    EXPECT_FALSE(cube.holds(under));
    const std::vector<FaceId> c = cube.candidates(right);
    EXPECT_TRUE(std::binary_search(c.begin(), c.end(), blocker)) << "G " << g;
    if (g >= 32) {
      // A small light: the two floor patches' volumes part ways below the floor.
      EXPECT_FALSE(std::binary_search(c.begin(), c.end(), left)) << "G " << g;
    }
    const std::vector<FacePair> pairs = cube.candidatePairs();
    EXPECT_TRUE(std::binary_search(pairs.begin(), pairs.end(), orderedPair(right, blocker)));
  }
}

TEST(OverlapCube, EditVolumeEnlargesTheCube) {
  const Scene scene = makeCubesScene(variedOptions(4));
  const OverlapCube standard(scene, 0);
  Bounds wide{scene.bounds().min - Vec3(10.0), scene.bounds().max + Vec3(10.0)};
  const OverlapCube widened(scene, 0, OverlapCubeSettings{0, wide});
  widened.validate();
  EXPECT_GT(widened.cubeSide(), standard.cubeSide());
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_LE(widened.cubeMin()[axis], wide.min[axis]);
    EXPECT_GE(widened.cubeMin()[axis] + widened.cubeSide(), wide.max[axis]);
  }
  // A face moved out of the cube is refused, and nothing changes.
  OverlapCube cube(scene, 0);
  Face far = scene.faces().back();
  cube.removeFace(far.id);
  for (Vec3& v : far.polygon) v += Vec3(2 * cube.cubeSide(), 0, 0);
  far.plane = Plane::throughPoint(far.plane.normal, far.polygon[0]);
  EXPECT_THROW(cube.insertFace(far), std::invalid_argument);
  EXPECT_FALSE(cube.holds(far.id));
  cube.validate();
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

// The pairs without one object's own, and each face's lowest same-object partner, against
// the full candidate pairs (seeded cube rooms: each cube an object of six faces; the room's
// faces are objects of one).
TEST(OverlapCube, SkippedPairsAndLowestPartnersMatchTheFullPairs) {
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    const Scene scene = makeCubesScene(variedOptions(seed));
    const OverlapCube cube(scene, 0);
    auto skip = [](uint32_t object) { return object % 3 == 1; };
    auto rank = [](FaceId f) { return size_t(f.object) * 131 + size_t(f.face) * 7 % 5; };
    const auto all = cube.candidatePairs();
    std::vector<std::pair<FaceId, FaceId>> expected;
    std::map<FaceId, size_t> lowest;
    for (const auto& [a, b] : all) {
      if (a.object == b.object && skip(a.object)) {
        for (const auto& [x, y] : {std::pair{a, b}, std::pair{b, a}}) {
          auto [it, added] = lowest.try_emplace(x, rank(y));
          if (!added) it->second = std::min(it->second, rank(y));
        }
        continue;
      }
      expected.push_back({a, b});
    }
    EXPECT_EQ(cube.candidatePairs(skip), expected) << "seed " << seed;
    const auto partners = cube.lowestSameObjectPartner(skip, rank);
    const std::map<FaceId, size_t> found(partners.begin(), partners.end());
    EXPECT_EQ(found, lowest) << "seed " << seed;
    EXPECT_FALSE(lowest.empty());
  }
}

}  // namespace
}  // namespace penumbra
