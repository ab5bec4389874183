#include "bench/lib/cubes_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

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

TEST(CubesScene, ObjectsDoNotInterpenetrateAndRestOnSomething) {
  size_t stackedSeen = 0;
  for (const CubesSceneOptions& options : variedOptions()) {
    const Scene scene = makeCubesScene(options);
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

}  // namespace
}  // namespace penumbra
