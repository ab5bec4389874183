#include "scenegen/cubes_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "protocol/json_text.h"
#include "protocol/scene_json.h"

namespace penumbra {
namespace {

struct Standing {
  size_t object = 0;
  std::vector<Vec2> footprint;  // xz of its largest downward face, CCW or CW
  Polygon3 bottom, top;         // largest downward and upward faces (world)
  double minY = 0, maxY = 0;
};

bool startsWith(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

Polygon3 largestFace(const Scene& scene, size_t object, double normalY) {
  Polygon3 best;
  double bestArea = -1;
  for (const Face& face : scene.faces())
    if (face.id.object == object && face.plane.normal.y * normalY > 0.5 && face.area > bestArea) {
      bestArea = face.area;
      best = face.polygon;
    }
  return best;
}

std::vector<Standing> standingObjects(const Scene& scene) {
  std::vector<Standing> out;
  for (size_t o = 0; o < scene.objects().size(); ++o) {
    const std::string& id = scene.objects()[o].id;
    if (!startsWith(id, "cube_") && !startsWith(id, "table_")) continue;
    Standing s;
    s.object = o;
    s.bottom = largestFace(scene, o, -1);
    s.top = largestFace(scene, o, 1);
    for (const Vec3& v : s.bottom) s.footprint.push_back(Vec2(v.x, v.z));
    s.minY = INFINITY;
    s.maxY = -INFINITY;
    for (const Face& face : scene.faces())
      if (face.id.object == o)
        for (const Vec3& v : face.polygon) {
          s.minY = std::min(s.minY, v.y);
          s.maxY = std::max(s.maxY, v.y);
        }
    out.push_back(std::move(s));
  }
  return out;
}

// Separating-axis test: do two convex 2D polygons overlap by more than eps?
bool footprintsOverlap(const std::vector<Vec2>& a, const std::vector<Vec2>& b, double eps) {
  for (const auto* poly : {&a, &b}) {
    for (size_t i = 0; i < poly->size(); ++i) {
      const Vec2 edge = (*poly)[(i + 1) % poly->size()] - (*poly)[i];
      const Vec2 axis = glm::normalize(Vec2(-edge.y, edge.x));
      double aMin = INFINITY, aMax = -INFINITY, bMin = INFINITY, bMax = -INFINITY;
      for (const Vec2& v : a) aMin = std::min(aMin, glm::dot(axis, v)), aMax = std::max(aMax, glm::dot(axis, v));
      for (const Vec2& v : b) bMin = std::min(bMin, glm::dot(axis, v)), bMax = std::max(bMax, glm::dot(axis, v));
      if (aMax <= bMin + eps || bMax <= aMin + eps) return false;
    }
  }
  return true;
}

// Is a point inside (or on) a convex polygon given in xz, either winding?
bool insideConvex(const Polygon3& polygon, const Vec3& p, double eps) {
  int sign = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec3& a = polygon[i];
    const Vec3& b = polygon[(i + 1) % polygon.size()];
    const double c = cross2(Vec2(b.x - a.x, b.z - a.z), Vec2(p.x - a.x, p.z - a.z));
    if (std::abs(c) <= eps) continue;
    const int s = c > 0 ? 1 : -1;
    if (sign != 0 && s != sign) return false;
    sign = s;
  }
  return true;
}

std::vector<CubesSceneOptions> variedOptions() {
  std::vector<CubesSceneOptions> out;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    CubesSceneOptions o;
    o.seed = seed;
    o.cubes = int(5 + 13 * seed);
    o.stackedFraction = 0.35;
    o.thinTables = seed % 2 ? 0.25 : 0.0;
    o.tiltedLight = seed % 3 == 0;
    o.twoLights = seed % 2 == 0;
    o.lightScale = seed == 4 ? 0.2 : 1.0;
    out.push_back(o);
  }
  return out;
}

TEST(CubesScene, DeterministicForASeed) {
  CubesSceneOptions options;
  options.cubes = 30;
  options.seed = 42;
  options.thinTables = 0.2;
  const Scene a = makeCubesScene(options), b = makeCubesScene(options);
  ASSERT_EQ(a.faces().size(), b.faces().size());
  for (size_t i = 0; i < a.faces().size(); ++i) EXPECT_EQ(a.faces()[i].polygon, b.faces()[i].polygon);
  options.seed = 43;
  const Scene c = makeCubesScene(options);
  bool differs = c.faces().size() != a.faces().size();
  for (size_t i = 0; !differs && i < a.faces().size(); ++i) differs = a.faces()[i].polygon != c.faces()[i].polygon;
  EXPECT_TRUE(differs);
}

TEST(CubesScene, CountsIdsAndMaterials) {
  for (const CubesSceneOptions& options : variedOptions()) {
    const Scene scene = makeCubesScene(options);
    size_t cubes = 0, tables = 0;
    for (const Object& object : scene.objects()) {
      cubes += startsWith(object.id, "cube_");
      tables += startsWith(object.id, "table_");
    }
    EXPECT_EQ(cubes + tables, size_t(options.cubes));
    if (options.thinTables == 0) {
      EXPECT_EQ(tables, 0u);
    } else {
      EXPECT_GT(tables, 0u);
    }
    EXPECT_EQ(scene.objects().size(), 6 + cubes + tables);
    EXPECT_EQ(scene.faces().size(), 6 + 6 * cubes + 30 * tables);
    for (const char* id : {"floor", "ceiling", "wall_n", "wall_s", "wall_e", "wall_w"})
      EXPECT_TRUE(scene.findObject(id)) << id;
    EXPECT_TRUE(scene.findMaterial("white") && scene.findMaterial("clay"));
    ASSERT_EQ(scene.lights().size(), options.twoLights ? 2u : 1u);
    EXPECT_EQ(scene.lights()[0].id, "light");
    EXPECT_TRUE(scene.camera());
  }
}

TEST(CubesScene, FacesAndLightsAreValid) {
  for (const CubesSceneOptions& options : variedOptions()) {
    const Scene scene = makeCubesScene(options);
    const CubesRoom room = cubesRoom(options);
    const double eps = scene.tolerance().length();
    for (const Face& face : scene.faces()) {
      EXPECT_LE(planarityError(face.polygon), kRelativePlanarity);
      EXPECT_TRUE(isConvex(face.polygon));
      for (const Vec3& v : face.polygon) {
        EXPECT_LE(std::abs(v.x), room.side / 2 + eps);
        EXPECT_LE(std::abs(v.z), room.side / 2 + eps);
        EXPECT_GE(v.y, -eps);
        EXPECT_LE(v.y, room.height + eps);
      }
    }
    // Cube and table faces point away from their object's centre.
    for (size_t o = 6; o < scene.objects().size(); ++o) {
      if (!startsWith(scene.objects()[o].id, "cube_")) continue;
      Vec3 centre{0.0};
      int count = 0;
      for (const Face& face : scene.faces())
        if (face.id.object == o) centre += centroid(face.polygon), ++count;
      centre /= double(count);
      for (const Face& face : scene.faces())
        if (face.id.object == o) {
          EXPECT_GT(glm::dot(face.plane.normal, centroid(face.polygon) - centre), 0);
        }
    }
    // Room faces point inwards.
    for (const Face& face : scene.faces())
      if (face.id.object < 6) {
        EXPECT_GT(face.plane.signedDistance(Vec3(0, room.height / 2, 0)), 0);
      }
    // Lights: convex, facing down-ish, below the ceiling, above every object.
    double highest = 0;
    for (const Standing& s : standingObjects(scene)) highest = std::max(highest, s.maxY);
    for (const Light& light : scene.lights()) {
      EXPECT_TRUE(isConvex(light.polygon));
      EXPECT_LE(planarityError(light.polygon), kRelativePlanarity);
      const Vec3 n = light.plane().normal;
      if (options.tiltedLight) {
        EXPECT_NEAR(n.y, -std::cos(glm::radians(25.0)), 1e-12);
      } else {
        EXPECT_DOUBLE_EQ(n.y, -1);
      }
      EXPECT_NEAR(light.area(), std::pow(1.5 * options.lightScale, 2), 1e-12);
      for (const Vec3& v : light.polygon) {
        EXPECT_LT(v.y, room.height);
        EXPECT_GT(v.y, highest);
      }
    }
  }
}

// Checks no two standing objects interpenetrate and each rests exactly on the
// floor or on a cube's top; returns how many rest on a cube.
size_t expectStandingProperly(const Scene& scene) {
  size_t stackedSeen = 0;
  {
    const double eps = scene.tolerance().length();
    const auto standing = standingObjects(scene);
    for (size_t i = 0; i < standing.size(); ++i) {
      const Standing& a = standing[i];
      for (size_t j = i + 1; j < standing.size(); ++j) {
        const Standing& b = standing[j];
        const bool verticalOverlap = std::min(a.maxY, b.maxY) > std::max(a.minY, b.minY) + eps;
        EXPECT_FALSE(verticalOverlap && footprintsOverlap(a.footprint, b.footprint, eps))
            << scene.objects()[a.object].id << " and " << scene.objects()[b.object].id;
      }
      // Exactly on the floor, or exactly on the top of another cube, its whole
      // bottom face inside that top.
      if (a.minY == 0) continue;
      bool supported = false;
      for (const Standing& b : standing) {
        if (&b == &a || b.maxY != a.minY || !startsWith(scene.objects()[b.object].id, "cube_")) continue;
        supported = std::all_of(a.bottom.begin(), a.bottom.end(), [&](const Vec3& v) {
          return v.y == b.maxY && insideConvex(b.top, v, eps);
        });
        if (supported) break;
      }
      EXPECT_TRUE(supported) << scene.objects()[a.object].id << " floats at y = " << a.minY;
      ++stackedSeen;
    }
  }
  return stackedSeen;
}

TEST(CubesScene, ObjectsDoNotInterpenetrateAndRestOnSomething) {
  size_t stackedSeen = 0;
  for (const CubesSceneOptions& options : variedOptions())
    stackedSeen += expectStandingProperly(makeCubesScene(options));
  EXPECT_GT(stackedSeen, 0u);  // stacking is exercised
}

TEST(CubesScene, RoomGrowsWithCount) {
  CubesSceneOptions small, large;
  small.cubes = 15;
  large.cubes = 600;
  EXPECT_LT(cubesRoom(small).side, cubesRoom(large).side);
  const Scene scene = makeCubesScene(large);
  EXPECT_EQ(scene.objects().size(), 606u);
}

// The subject cube (issue 4's "same cube at every N"): the same object at every
// count and seed, 1.5 m along +x from the light, standing on the floor.
TEST(CubesSceneSubject, SameCubeAtTheSamePlaceAtEverySize) {
  std::string first;
  for (uint64_t seed : {1u, 2u})
    for (int cubes : {150, 1500, 5000}) {
      SCOPED_TRACE(std::to_string(cubes) + " cubes, seed " + std::to_string(seed));
      CubesSceneOptions options;
      options.cubes = cubes;
      options.seed = seed;
      options.subjectCube = true;
      const Scene scene = makeCubesScene(options);
      const auto index = scene.findObject(kSubjectCubeId);
      ASSERT_TRUE(index);
      EXPECT_EQ(*index, scene.objects().size() - 1);  // listed last
      const Object& subject = scene.objects()[*index];
      EXPECT_FALSE(subject.isStatic);
      EXPECT_EQ(subject.material, "clay");
      EXPECT_EQ(subject.transform.translate, Vec3(1.5, 0.25, 0));
      EXPECT_EQ(subject.transform.scale, Vec3(0.5));
      // Its faces in world space: a 0.5 m cube from y = 0 to 0.5, centred 1.5 m
      // from the light's centre (x = z = 0) — and identical at every size.
      double minY = INFINITY, maxY = -INFINITY;
      Vec2 sum{0.0};
      int count = 0;
      for (const Face& face : scene.faces())
        if (face.id.object == *index)
          for (const Vec3& v : face.polygon) {
            minY = std::min(minY, v.y), maxY = std::max(maxY, v.y);
            sum += Vec2(v.x, v.z), ++count;
          }
      EXPECT_EQ(count, 24);
      EXPECT_EQ(minY, 0);
      EXPECT_EQ(maxY, 0.5);
      EXPECT_NEAR(glm::length(sum / double(count) - Vec2(1.5, 0)), 0, 1e-12);
      const std::string json = protocol::sceneToJson(Scene({}, scene.materials(), {subject}, std::nullopt)).dump();
      if (first.empty()) first = json;
      EXPECT_EQ(json, first);
      // And the objects around it still stand properly (moved stacks included).
      if (cubes <= 1500) expectStandingProperly(scene);
    }
}

// Switching the subject on adds it, moves the floor objects (with their stacks,
// in x and z only) that were in its corridor, and changes nothing else.
TEST(CubesSceneSubject, OnlyAddsTheSubjectAndMovesWhatBlocksItsCorridor) {
  size_t movedSeen = 0;
  std::vector<CubesSceneOptions> all = variedOptions();
  for (int cubes : {150, 1500}) {
    CubesSceneOptions o;
    o.cubes = cubes;
    all.push_back(o);
  }
  for (CubesSceneOptions options : all) {
    SCOPED_TRACE(std::to_string(options.cubes) + " cubes, seed " + std::to_string(options.seed));
    const Scene off = makeCubesScene(options);
    options.subjectCube = true;
    const Scene on = makeCubesScene(options);
    ASSERT_EQ(on.objects().size(), off.objects().size() + 1);
    EXPECT_EQ(on.objects().back().id, kSubjectCubeId);
    EXPECT_EQ(protocol::sceneToJson(Scene(on.lights(), on.materials(), {}, on.camera())),
              protocol::sceneToJson(Scene(off.lights(), off.materials(), {}, off.camera())));
    std::map<std::string, Vec3> shifts;  // moved object → its shift
    for (size_t i = 0; i < off.objects().size(); ++i) {
      const Object& a = off.objects()[i];
      const Object& b = on.objects()[i];
      ASSERT_EQ(a.id, b.id);
      EXPECT_EQ(a.vertices, b.vertices);
      EXPECT_EQ(a.faces, b.faces);
      EXPECT_EQ(a.material, b.material);
      EXPECT_EQ(a.transform.rotateDeg, b.transform.rotateDeg);
      EXPECT_EQ(a.transform.scale, b.transform.scale);
      EXPECT_EQ(a.transform.translate.y, b.transform.translate.y);
      if (a.transform.translate != b.transform.translate)
        shifts[a.id] = b.transform.translate - a.transform.translate;
    }
    // A moved cube resting on another moved with it, by the same shift.
    for (const auto& [id, shift] : shifts) {
      const Object& object = on.objects()[*on.findObject(id)];
      const bool onFloor = startsWith(id, "table_") ||  // tables' origin is at the floor
                           object.transform.translate.y == 0.5 * object.transform.scale.y;
      if (onFloor) continue;
      bool withItsSupport = false;
      for (const auto& [other, otherShift] : shifts)
        withItsSupport |= other != id && glm::length(otherShift - shift) < 1e-12;
      EXPECT_TRUE(withItsSupport) << id;
    }
    movedSeen += shifts.size();
    expectStandingProperly(on);
  }
  EXPECT_GT(movedSeen, 0u);  // the corridor did have to be cleared somewhere
}

// The option off is the generator's output as shipped: scenes/cubes15.scene.json
// was written by `penumbra generate --cubes 15 --seed 15`.
TEST(CubesSceneSubject, OffIsTheShippedGeneratorOutput) {
  CubesSceneOptions options;
  options.cubes = 15;
  options.seed = 15;
  options.subjectCube = false;
  const Scene generated = makeCubesScene(options);
  const Scene shipped =
      protocol::loadSceneFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cubes15.scene.json");
  EXPECT_EQ(protocol::sceneToJson(generated), protocol::sceneToJson(shipped));
}

}  // namespace
}  // namespace penumbra
