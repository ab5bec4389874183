#include "core/order/face_order.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <random>
#include <set>
#include <sstream>

#include "core/geom/convex2d.h"
#include "core/geom/plane_frame.h"
#include "protocol/scene_json.h"
#include "scenegen/cubes_scene.h"

namespace penumbra {
namespace {

// Rays whose hit lies this close to a face's or fragment's boundary are ambiguous
// (a measure-zero set for sampling) and skipped; the test asserts they are rare.
double ambiguityBand(const Tolerance& tolerance) { return tolerance.onPlane(); }

double minEdgeDistance(const Polygon2& polygon, const Vec2& p) {
  double least = INFINITY;
  for (size_t i = 0; i < polygon.size(); ++i)
    least = std::min(least, lineDistance(polygon[i], polygon[(i + 1) % polygon.size()], p));
  return least;
}

Vec3 samplePolygon(const Polygon3& polygon, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> weights;
  for (size_t k = 1; k + 1 < polygon.size(); ++k)
    weights.push_back(glm::length(glm::cross(polygon[k] - polygon[0], polygon[k + 1] - polygon[0])));
  std::discrete_distribution<size_t> pick(weights.begin(), weights.end());
  const size_t k = pick(rng) + 1;
  double a = u(rng), b = u(rng);
  if (a + b > 1) a = 1 - a, b = 1 - b;
  return polygon[0] + a * (polygon[k] - polygon[0]) + b * (polygon[k + 1] - polygon[0]);
}

struct RayStats {
  size_t rays = 0, skipped = 0, hits = 0, pairs = 0, violations = 0;
  std::string firstViolation;
};

// The defining property: faces a ray from the light crosses through their front side,
// nearest first, come in increasing fragment order. `present` says which scene faces
// are in the order (all, or those left after removals).
RayStats checkRays(const Scene& scene, size_t light, const FaceOrder& order,
                   const std::function<bool(FaceId)>& present, size_t rays, uint64_t seed) {
  const Tolerance tolerance = scene.tolerance();
  const double band = ambiguityBand(tolerance);
  const Light& source = scene.lights()[light];
  const Vec3 lightNormal = source.plane().normal;
  struct Prepared {
    PlaneFrame frame;
    Polygon2 polygon;
    std::vector<std::pair<size_t, Polygon2>> fragments;  // walk index, 2D polygon
  };
  std::map<FaceId, Prepared> faces;
  for (const Face& face : scene.faces()) {
    if (!present(face.id) || face.area <= tolerance.area()) continue;
    Prepared p;
    p.frame = PlaneFrame::onPlane(face.plane, face.polygon[0]);
    for (const Vec3& v : face.polygon) p.polygon.push_back(p.frame.to2D(v));
    faces.emplace(face.id, std::move(p));
  }
  const auto& walk = order.fragments();
  for (size_t i = 0; i < walk.size(); ++i) {
    auto it = faces.find(walk[i].face);
    if (it == faces.end()) continue;  // reported by the presence checks
    Polygon2 q;
    for (const Vec3& v : walk[i].polygon) q.push_back(it->second.frame.to2D(v));
    it->second.fragments.push_back({i, std::move(q)});
  }

  RayStats stats;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss;
  for (size_t r = 0; r < rays; ++r) {
    ++stats.rays;
    const Vec3 origin = samplePolygon(source.polygon, rng);
    Vec3 dir{gauss(rng), gauss(rng), gauss(rng)};
    if (glm::dot(dir, lightNormal) < 0) dir = -dir;
    dir = glm::normalize(dir);
    std::vector<std::pair<double, size_t>> hits;  // t, fragment index
    bool ambiguous = false;
    for (const Face& face : scene.faces()) {
      auto it = faces.find(face.id);
      if (it == faces.end()) continue;
      const double d = face.plane.signedDistance(origin);
      const double denom = glm::dot(face.plane.normal, dir);
      if (d <= tolerance.length() || denom >= 0) continue;  // not a crossing through the front
      const Vec3 point = origin + (-d / denom) * dir;
      const Vec2 p2 = it->second.frame.to2D(point);
      const double inside = minEdgeDistance(it->second.polygon, p2);
      if (inside < -band) continue;
      if (inside <= band) { ambiguous = true; break; }
      double best = -INFINITY;
      size_t bestIndex = SIZE_MAX;
      for (const auto& [index, fragment] : it->second.fragments) {
        const double m = minEdgeDistance(fragment, p2);
        if (m > best) best = m, bestIndex = index;
      }
      if (best <= band) { ambiguous = true; break; }
      hits.push_back({-d / denom, bestIndex});
    }
    if (ambiguous) { ++stats.skipped; continue; }
    std::sort(hits.begin(), hits.end());
    stats.hits += hits.size();
    if (!hits.empty()) stats.pairs += hits.size() - 1;
    for (size_t k = 1; k < hits.size(); ++k)
      if (hits[k].second <= hits[k - 1].second) {
        if (stats.violations++ == 0) {
          std::ostringstream s;
          const FaceId a = walk[hits[k - 1].second].face, b = walk[hits[k].second].face;
          s << "ray " << r << ": face (" << a.object << "," << a.face << ") fragment "
            << hits[k - 1].second << " is hit before face (" << b.object << "," << b.face
            << ") fragment " << hits[k].second;
          stats.firstViolation = s.str();
        }
        break;
      }
  }
  return stats;
}

void expectMembership(const Scene& scene, size_t light, const FaceOrder& order) {
  size_t front = 0, offending = 0;
  for (const Face& face : scene.faces()) {
    const FaceClass kind = scene.classify(face, scene.lights()[light]);
    if (kind == FaceClass::Back || face.area <= scene.tolerance().area()) {
      EXPECT_FALSE(order.contains(face.id)) << "back face in the order";
      continue;
    }
    EXPECT_TRUE(order.contains(face.id));
    ++(kind == FaceClass::Front ? front : offending);
  }
  EXPECT_EQ(order.counters().frontFaces, front);
  EXPECT_EQ(order.counters().offendingFaces, offending);
  for (const OrderedFragment& f : order.fragments()) {
    const Face& face = *std::find_if(scene.faces().begin(), scene.faces().end(),
                                     [&](const Face& x) { return x.id == f.face; });
    EXPECT_NE(scene.classify(face, scene.lights()[light]), FaceClass::Back);
  }
  const auto faces = order.faceOrder();
  for (size_t i = 0; i < faces.size(); ++i) EXPECT_EQ(order.rank(faces[i]), i);
}

// Returns the number of consecutive hit pairs checked (rays crossing k faces give k - 1).
size_t expectOrdered(const Scene& scene, size_t light, const FaceOrder& order,
                     const std::function<bool(FaceId)>& present, size_t rays, uint64_t seed,
                     const std::string& what) {
  const RayStats stats = checkRays(scene, light, order, present, rays, seed);
  EXPECT_EQ(stats.violations, 0u) << what << ": " << stats.firstViolation;
  EXPECT_LE(stats.skipped * 100, stats.rays) << what << ": too many ambiguous rays";
  return stats.pairs;
}

CubesSceneOptions generatedOptions(uint64_t seed) {
  CubesSceneOptions o;
  o.seed = seed;
  o.cubes = 3 + static_cast<int>(seed % 18);
  o.stackedFraction = seed % 4 == 0 ? 0.5 : 0.2;
  o.thinTables = seed % 3 == 0 ? 0.3 : 0.0;
  o.tiltedLight = seed % 2 == 1;
  o.twoLights = seed % 5 == 2;
  o.lightScale = seed % 7 == 3 ? 0.2 : 1.0;
  return o;
}

TEST(FaceOrder, RaysCrossFragmentsInOrderOnGeneratedScenes) {
  size_t sorted = 0, offending = 0, splits = 0, broken = 0, orders = 0, pairs = 0;
  for (uint64_t seed = 1; seed <= 110; ++seed) {
    const Scene scene = makeCubesScene(generatedOptions(seed));
    for (size_t light = 0; light < scene.lights().size(); ++light) {
      const FaceOrder order(scene, light);
      ASSERT_NO_THROW(order.validate()) << "seed " << seed << " light " << light;
      expectMembership(scene, light, order);
      pairs += expectOrdered(scene, light, order, [](FaceId) { return true; }, 2000, seed * 31 + light,
                    "seed " + std::to_string(seed) + " light " + std::to_string(light));
      sorted += order.counters().offendingCellsSorted;
      offending += order.counters().offendingFaces;
      splits += order.counters().cycleSplits;
      broken += order.counters().cyclesBroken;
      ++orders;
    }
  }
  // The generated scenes must exercise the graph method, not only the BSP walk.
  EXPECT_GT(offending, 0u);
  EXPECT_GT(sorted, 0u);
  EXPECT_GT(pairs, 10000u);
  std::printf("orders %zu, offending faces %zu, cells sorted %zu, cycle splits %zu, broken %zu, "
              "hit pairs checked %zu\n", orders, offending, sorted, splits, broken, pairs);
}

TEST(FaceOrder, RaysCrossFragmentsInOrderOnDemoScenes) {
  for (const char* name : {"cornell", "cubes15", "office"}) {
    const Scene scene = protocol::loadSceneFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" +
                                                name + ".scene.json");
    for (size_t light = 0; light < scene.lights().size(); ++light) {
      const FaceOrder order(scene, light);
      ASSERT_NO_THROW(order.validate()) << name;
      expectMembership(scene, light, order);
      EXPECT_GT(expectOrdered(scene, light, order, [](FaceId) { return true; }, 20000, 7 + light,
                              name),
                200u);
    }
  }
}

Object quad(const std::string& id, Polygon3 corners) {
  Object object;
  object.id = id;
  object.vertices = std::move(corners);
  object.faces = {{0, 1, 2, 3}};
  return object;
}

// Three vertical faces whose planes all cut the light: no front face, one cell,
// so only the graph method orders them.
TEST(FaceOrder, OffendingFacesSharingACellAreSortedByTheGraph) {
  const Light lamp{"lamp", {{-0.5, 3, -0.5}, {0.5, 3, -0.5}, {0.5, 3, 0.5}, {-0.5, 3, 0.5}}, Vec3{10}};
  ASSERT_LT(lamp.plane().normal.y, 0);
  // Facing +x at x = 0.1 and x = -0.2 (quads CCW seen from +x), facing +z at z = 0.
  const Object a = quad("a", {{0.1, 1, -1}, {0.1, 2, -1}, {0.1, 2, 1}, {0.1, 1, 1}});
  const Object b = quad("b", {{-0.2, 0, -1}, {-0.2, 1.5, -1}, {-0.2, 1.5, 1}, {-0.2, 0, 1}});
  const Object c = quad("c", {{-2, 0, 0}, {2, 0, 0}, {2, 0.8, 0}, {-2, 0.8, 0}});
  const Scene scene({lamp}, {}, {a, b, c});
  for (const Face& face : scene.faces())
    ASSERT_EQ(scene.classify(face, scene.lights()[0]), FaceClass::Offending);
  const FaceOrder order(scene, 0);
  order.validate();
  EXPECT_EQ(order.counters().nodes, 0u);
  EXPECT_EQ(order.counters().offendingCellsSorted, 1u);
  EXPECT_EQ(order.counters().cyclesBroken, 0u);
  EXPECT_LT(order.rank(FaceId{0, 0}), order.rank(FaceId{1, 0}));  // a shadows b
  EXPECT_GT(expectOrdered(scene, 0, order, [](FaceId) { return true; }, 200000, 3, "three offending"),
            200u);
}

// Random vertical quads (random heights, yaw, facing) under a large light: most of
// them offending, crowded into few cells, so the graph method and its cycle
// splitting decide the order.
Scene pickets(uint64_t seed, int count) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const Light lamp{"lamp", {{-1, 3, -1}, {1, 3, -1}, {1, 3, 1}, {-1, 3, 1}}, Vec3{10}};
  std::vector<Object> objects{quad("floor", {{-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}})};
  for (int i = 0; i < count; ++i) {
    const Vec3 center{-1.5 + 3 * u(rng), 0.3 + 2 * u(rng), -1.5 + 3 * u(rng)};
    const double yaw = 2 * M_PI * u(rng), half = 0.2 + 0.5 * u(rng), high = 0.1 + 0.4 * u(rng);
    const Vec3 along{std::cos(yaw) * half, 0, std::sin(yaw) * half}, up{0, high, 0};
    objects.push_back(quad("q" + std::to_string(i), {center - along - up, center + along - up,
                                                     center + along + up, center - along + up}));
  }
  return Scene({lamp}, {}, std::move(objects));
}

TEST(FaceOrder, RaysCrossFragmentsInOrderAmongCrowdedOffendingFaces) {
  size_t splits = 0, broken = 0, sorted = 0, pairs = 0;
  for (uint64_t seed = 1; seed <= 40; ++seed) {
    const Scene scene = pickets(seed, 4 + static_cast<int>(seed % 12));
    const FaceOrder order(scene, 0);
    ASSERT_NO_THROW(order.validate()) << "seed " << seed;
    expectMembership(scene, 0, order);
    splits += order.counters().cycleSplits;
    broken += order.counters().cyclesBroken;
    sorted += order.counters().offendingCellsSorted;
    pairs += expectOrdered(scene, 0, order, [](FaceId) { return true; }, 20000, seed,
                           "pickets seed " + std::to_string(seed));
  }
  EXPECT_GT(sorted, 0u);
  EXPECT_GT(splits, 0u);
  EXPECT_EQ(broken, 0u) << "splitting by cycle members' planes opened every cycle so far";
  EXPECT_GT(pairs, 5000u);
  std::printf("pickets: cells sorted %zu, cycle splits %zu, cycles broken %zu, pairs %zu\n",
              sorted, splits, broken, pairs);
}

TEST(FaceOrder, BackFacesAreLeftOut) {
  const Light lamp{"lamp", {{-0.5, 3, -0.5}, {0.5, 3, -0.5}, {0.5, 3, 0.5}, {-0.5, 3, 0.5}}, Vec3{10}};
  // A floor facing up (front), the same floor facing down (back), a face above the light.
  const Object up = quad("up", {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}});
  const Object down = quad("down", {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}});
  const Object above = quad("above", {{-1, 4, -1}, {-1, 4, 1}, {1, 4, 1}, {1, 4, -1}});
  const Scene scene({lamp}, {}, {up, down, above});
  const FaceOrder order(scene, 0);
  order.validate();
  EXPECT_TRUE(order.contains(FaceId{0, 0}));
  EXPECT_FALSE(order.contains(FaceId{1, 0}));
  EXPECT_FALSE(order.contains(FaceId{2, 0}));
  EXPECT_EQ(order.faceOrder().size(), 1u);
  EXPECT_THROW(order.rank(FaceId{1, 0}), std::out_of_range);
}

// Removing objects and adding them back keeps every invariant and the ray property
// of the scene that remains (the constraints a fresh build of it would satisfy).
TEST(FaceOrder, RemoveAndInsertKeepTheOrder) {
  for (uint64_t seed = 1; seed <= 24; ++seed) {
    CubesSceneOptions options = generatedOptions(seed);
    const Scene scene = makeCubesScene(options);
    std::mt19937_64 rng(seed);
    for (size_t light = 0; light < scene.lights().size(); ++light) {
      FaceOrder order(scene, light);
      std::set<uint32_t> removed;
      auto present = [&](FaceId f) { return removed.count(f.object) == 0; };
      for (int round = 0; round < 3; ++round) {
        const uint32_t object =
            std::uniform_int_distribution<uint32_t>(0, scene.objects().size() - 1)(rng);
        if (!removed.insert(object).second) continue;
        for (const Face& face : scene.faces())
          if (face.id.object == object) {
            order.removeFace(face.id);
            ASSERT_NO_THROW(order.validate()) << "seed " << seed << " remove " << object;
            EXPECT_FALSE(order.contains(face.id));
          }
        expectOrdered(scene, light, order, present, 400, seed + round,
                      "seed " + std::to_string(seed) + " after removing " + std::to_string(object));
      }
      for (uint32_t object : std::vector<uint32_t>(removed.begin(), removed.end())) {
        removed.erase(object);
        for (const Face& face : scene.faces())
          if (face.id.object == object) {
            order.insertFace(face);
            ASSERT_NO_THROW(order.validate()) << "seed " << seed << " insert " << object;
          }
        expectOrdered(scene, light, order, present, 400, seed + 100 + object,
                      "seed " + std::to_string(seed) + " after adding " + std::to_string(object));
      }
      expectMembership(scene, light, order);
    }
  }
}

}  // namespace
}  // namespace penumbra
