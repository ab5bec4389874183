// illuminateVertex / illuminatePoint against ExactReference on generated scenes,
// with cells built from the truth (exact set, superset, several cells); §2.4's
// case order at D⁰ vertices; and the one-sided limit at D⁰ contacts.
#include "core/illum/vertex_illumination.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "core/illum/backprojection.h"
#include "core/raycast/ray_scene.h"
#include "tests/core/illum/truth.h"

namespace penumbra {
namespace {

using namespace illum_test;

// 1e-9 relative, with a floor of 1e-12 of the scene's peak.
void expectClose(double mine, double truth, double peak, const char* what) {
  EXPECT_LE(std::abs(mine - truth), 1e-9 * std::abs(truth) + 1e-12 * peak)
      << what << ": " << mine << " vs " << truth;
}

struct Cells {
  std::vector<OccluderList> lists;
  std::vector<const OccluderList*> pointers() const {
    std::vector<const OccluderList*> out;
    for (const OccluderList& l : lists) out.push_back(&l);
    return out;
  }
};

struct Stats {
  size_t points = 0, penumbra = 0, penumbraComparisons = 0, umbraByFlag = 0;
  size_t lit = 0, umbra = 0;
};

// Checks one point of one scene in the three cell configurations.
void checkPoint(const Scene& scene, const ExactReference& reference, double peak,
                const Vec3& p, const Vec3& n, std::mt19937_64& rng, Stats& stats) {
  const size_t lights = scene.lights().size();
  const size_t faceCount = scene.faces().size();
  std::vector<std::vector<FaceId>> truth(lights), umbraFaces(lights);
  std::vector<LightVisibility> expected(lights);
  for (size_t l = 0; l < lights; ++l) {
    truth[l] = blockersOf(scene, l, p, n);
    expected[l] = reference.visibility(p, n, l);
    if (expected[l].lightClass == LightClass::Umbra && expected[l].unoccludedFactor > 0)
      for (const FaceId& f : truth[l])
        for (const Face& face : scene.faces())
          if (face.id == f && hidesAlone(scene, l, face, p, n)) umbraFaces[l].push_back(f);
  }
  auto extras = [&](size_t count) {
    std::vector<FaceId> out;
    for (size_t i = 0; i < count; ++i)
      out.push_back(scene.faces()[std::uniform_int_distribution<size_t>(0, faceCount - 1)(rng)].id);
    return out;
  };

  // (a) the exact set, (b) a superset, (c) three cells whose intersection is the set.
  Cells exact, superset, several;
  exact.lists.resize(1);
  superset.lists.resize(1);
  several.lists.resize(3);
  for (size_t l = 0; l < lights; ++l) {
    appendEntries(exact.lists[0], uint32_t(l), truth[l], umbraFaces[l]);
    appendEntries(superset.lists[0], uint32_t(l), unite(truth[l], extras(6)), umbraFaces[l]);
    std::vector<FaceId> spare = extras(9);
    std::erase_if(spare, [&](const FaceId& f) {
      return std::find(truth[l].begin(), truth[l].end(), f) != truth[l].end();
    });
    for (size_t c = 0; c < 3; ++c) {
      std::vector<FaceId> own;
      for (size_t i = c; i < spare.size(); i += 3)
        if (std::count(spare.begin(), spare.end(), spare[i]) == 1) own.push_back(spare[i]);
      appendEntries(several.lists[c], uint32_t(l), unite(truth[l], own), umbraFaces[l]);
    }
  }

  for (const Cells* cells : {&exact, &superset, &several}) {
    const auto around = cells->pointers();
    for (size_t l = 0; l < lights; ++l) {
      const VertexLight mine = illuminateVertex(scene, l, p, n, n, around);
      const double lightPeak = peak / maxAbs(scene.lights()[l].radiance);
      if (!mine.applies()) {
        EXPECT_EQ(expected[l].unoccludedFactor, 0.0);
        continue;
      }
      expectClose(mine.factor(), expected[l].visibleFactor, lightPeak, "factor");
      expectClose(Backprojection(scene, l, p, n).unoccludedFactor(), expected[l].unoccludedFactor, lightPeak, "unoccluded");
      EXPECT_EQ(mine.lightClass(), expected[l].lightClass)
          << "p=(" << p.x << "," << p.y << "," << p.z << ") light " << l;
      if (cells == &exact) {
        ++stats.points;
        if (mine.lightClass() == LightClass::Penumbra) {
          ++stats.penumbra;
          stats.penumbraComparisons += mine.comparisons();
        }
        stats.lit += mine.lightClass() == LightClass::Lit;
        stats.umbra += mine.lightClass() == LightClass::Umbra;
        stats.umbraByFlag += mine.decidedBy() == VertexCase::Umbra;
        if (truth[l].empty()) {
          EXPECT_EQ(mine.decidedBy(), VertexCase::Unoccluded);
        }
      }
    }
    const VertexIrradiance all = illuminatePoint(scene, p, n, n, around);
    const PointIrradiance ref = reference.evaluate(p, n);
    for (int c = 0; c < 3; ++c) expectClose(all.irradiance[c], ref.irradiance[c], peak, "irradiance");
    EXPECT_EQ(all.lightClass, ref.lightClass);
  }
}

TEST(IlluminateVertex, MatchesReferenceOnGeneratedScenes) {
  Stats stats;
  constexpr int kScenes = 120;
  constexpr int kPointsPerScene = 40;
  for (int k = 0; k < kScenes; ++k) {
    SCOPED_TRACE("scene " + std::to_string(k));
    const Scene scene = makeCubesScene(sceneOptions(k));
    const ExactReference reference(scene);
    const double peak = peakIrradiance(scene);
    std::vector<const Face*> receivers;
    for (const Face& f : scene.faces())
      if (scene.receivesLight(f)) receivers.push_back(&f);
    std::mt19937_64 rng(k);
    for (int i = 0; i < kPointsPerScene; ++i) {
      const Face& face = *receivers[std::uniform_int_distribution<size_t>(0, receivers.size() - 1)(rng)];
      // Mostly interior points; some face corners (on neighbouring faces' planes).
      const Vec3 p = i % 8 == 7 ? face.polygon[size_t(i / 8) % face.polygon.size()]
                                : randomPointOn(face, rng);
      checkPoint(scene, reference, peak, p, face.plane.normal, rng, stats);
      if (HasFailure()) return;
    }
  }
  ASSERT_GT(stats.penumbra, 100u);
  ASSERT_GT(stats.umbraByFlag, 0u);
  const double mean = double(stats.penumbraComparisons) / double(stats.penumbra);
  std::printf("[illum] %zu (point, light) pairs: %zu lit, %zu penumbra, %zu umbra (%zu by an umbra flag); "
              "comparisons per penumbra vertex %.2f\n",
              stats.points, stats.lit, stats.penumbra, stats.umbra, stats.umbraByFlag, mean);
  RecordProperty("comparisons_per_penumbra_vertex", std::to_string(mean));
}

// The test's truth set really holds every face that blocks a sampled ray (checked
// with Embree's blockers, an independent path).
TEST(IlluminateVertex, TruthSetHoldsEverySampledBlocker) {
  for (int k = 0; k < 12; ++k) {
    const Scene scene = makeCubesScene(sceneOptions(k));
    const RayScene rays(scene);
    std::mt19937_64 rng(100 + k);
    std::uniform_real_distribution<double> u(0, 1);
    const Face& floor = scene.faces()[0];
    for (int i = 0; i < 40; ++i) {
      const Vec3 p = randomPointOn(floor, rng);
      for (size_t l = 0; l < scene.lights().size(); ++l) {
        const std::vector<FaceId> truth = blockersOf(scene, l, p, floor.plane.normal);
        const Face lightFace{FaceId{}, scene.lights()[l].polygon, scene.lights()[l].plane(), 0};
        for (int s = 0; s < 16; ++s) {
          const Vec3 q = randomPointOn(lightFace, rng);
          for (uint32_t index : rays.blockers(p, q)) {
            const FaceId id = scene.faces()[index].id;
            EXPECT_NE(std::find(truth.begin(), truth.end(), id), truth.end());
          }
        }
      }
    }
  }
}

// ---- D⁰ contacts ---------------------------------------------------------------

// A point on the line where an object's bottom face rests on a receiver face.
struct Contact {
  Vec3 p{0.0};
  Vec3 normal{0, 1, 0};   // the receiver's
  Vec3 inside{0.0};       // unit, in the receiver's plane, under the object
  const Face* side = nullptr;  // the object's face whose plane contains p
  uint32_t object = 0;
  bool corner = false;
};

std::vector<Contact> contactsOf(const Scene& scene, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.2, 0.8);
  const double eps = scene.tolerance().length();
  std::vector<Contact> out;
  for (const Face& bottom : scene.faces()) {
    if (bottom.plane.normal.y > -1 + 1e-12) continue;
    const double y = bottom.polygon[0].y;
    const Polygon3& b = bottom.polygon;
    for (size_t i = 0; i < b.size(); ++i) {
      const Vec3 a = b[i], c = b[(i + 1) % b.size()];
      const Face* side = nullptr;
      for (const Face& f : scene.faces())
        if (f.id.object == bottom.id.object && std::abs(f.plane.normal.y) < 1e-12 &&
            std::abs(f.plane.signedDistance(a)) < eps && std::abs(f.plane.signedDistance(c)) < eps)
          side = &f;
      if (!side) continue;
      Contact contact;
      contact.p = a + u(rng) * (c - a);
      contact.inside = -side->plane.normal;
      contact.side = side;
      contact.object = bottom.id.object;
      // The receiver: an upward face at the same height holding p and both sides of it.
      bool onReceiver = false;
      for (const Face& r : scene.faces()) {
        if (r.plane.normal.y < 1 - 1e-12 || std::abs(r.polygon[0].y - y) > eps) continue;
        if (r.id.object == bottom.id.object) continue;
        bool holds = true;
        for (double s : {-1e-3, 1e-3}) {
          const Vec3 q = contact.p + s * contact.inside;
          for (size_t j = 0; j < r.polygon.size(); ++j) {
            const Vec3 e = r.polygon[(j + 1) % r.polygon.size()] - r.polygon[j];
            if (glm::dot(glm::cross(e, q - r.polygon[j]), r.plane.normal) < 0) holds = false;
          }
        }
        onReceiver |= holds;
      }
      if (onReceiver) out.push_back(contact);
    }
  }
  return out;
}

// The truth set at p, at points beside it, and optionally an object's faces.
std::vector<FaceId> blockersNear(const Scene& scene, size_t l, const Contact& c, const Vec3& d,
                                 std::initializer_list<double> deltas) {
  std::vector<FaceId> out = blockersOf(scene, l, c.p, c.normal);
  for (double delta : deltas) out = unite(out, blockersOf(scene, l, c.p + delta * d, c.normal));
  return out;
}

std::vector<FaceId> facesOfObject(const Scene& scene, uint32_t object) {
  std::vector<FaceId> out;
  for (const Face& f : scene.faces())
    if (f.id.object == object) out.push_back(f.id);
  return out;
}

TEST(IlluminateVertex, D0VertexBesideUmbraCellIsNeverDark) {
  size_t litBesideUmbra = 0, penumbraBesideUmbra = 0, checked = 0;
  for (int k = 0; k < 60; ++k) {
    const Scene scene = makeCubesScene(sceneOptions(k));
    const ExactReference reference(scene);
    const double peak = peakIrradiance(scene);
    std::mt19937_64 rng(500 + k);
    for (const Contact& c : contactsOf(scene, rng)) {
      // Inside: everything under the object, its side face flagged umbra where it
      // alone hides the light just behind it. Outside: the truth at p.
      OccluderList inside, outside;
      bool flagged = false;
      for (size_t l = 0; l < scene.lights().size(); ++l) {
        const Vec3 behind = c.p + 1e-4 * c.inside;
        std::vector<FaceId> umbra;
        if (hidesAlone(scene, l, *c.side, behind, c.normal)) umbra.push_back(c.side->id);
        flagged |= !umbra.empty();
        appendEntries(inside, uint32_t(l),
                      unite(blockersNear(scene, l, c, c.inside, {1e-4}), facesOfObject(scene, c.object)),
                      umbra);
        appendEntries(outside, uint32_t(l), blockersOf(scene, l, c.p, c.normal));
      }
      if (!flagged) continue;
      ++checked;
      const VertexIrradiance mine = illuminatePoint(scene, c.p, c.normal, c.normal, {&inside, &outside});
      const PointIrradiance ref = reference.evaluate(c.p, c.normal);
      for (int ch = 0; ch < 3; ++ch) expectClose(mine.irradiance[ch], ref.irradiance[ch], peak, "D0");
      EXPECT_EQ(mine.lightClass, ref.lightClass);
      if (maxAbs(ref.irradiance) > 0) {
        EXPECT_GT(maxAbs(mine.irradiance), 0.0);
        EXPECT_NE(mine.lightClass, LightClass::Umbra);
      }
      litBesideUmbra += mine.lightClass == LightClass::Lit;
      penumbraBesideUmbra += mine.lightClass == LightClass::Penumbra;
    }
  }
  std::printf("[illum] D0 vertices beside an umbra cell: %zu (%zu lit, %zu penumbra)\n", checked,
              litBesideUmbra, penumbraBesideUmbra);
  EXPECT_GT(litBesideUmbra, 5u);
  EXPECT_GT(penumbraBesideUmbra, 5u);
}

// A vertex with an umbra face in every cell is umbra without a comparison.
TEST(IlluminateVertex, UmbraFlagInEveryCellDecides) {
  const Scene scene = makeCubesScene(sceneOptions(0));
  std::mt19937_64 rng(3);
  size_t done = 0;
  for (const Contact& c : contactsOf(scene, rng)) {
    const Vec3 p = c.p + 0.05 * c.inside;  // under the object, away from its edges
    const Face* top = nullptr;
    for (const Face& f : scene.faces())
      if (f.id.object == c.object && f.plane.normal.y > 1 - 1e-12) top = &f;
    ASSERT_NE(top, nullptr);
    OccluderList a, b;
    appendEntries(a, 0, facesOfObject(scene, c.object), {top->id});
    appendEntries(b, 0, facesOfObject(scene, c.object), {top->id});
    const VertexLight v = illuminateVertex(scene, 0, p, c.normal, c.normal, {&a, &b});
    EXPECT_EQ(v.decidedBy(), VertexCase::Umbra);
    EXPECT_EQ(v.factor(), 0.0);
    EXPECT_EQ(v.lightClass(), LightClass::Umbra);
    EXPECT_EQ(v.comparisons(), 0u);
    EXPECT_EQ(ExactReference(scene).visibility(p, c.normal, 0).visibleFactor, 0.0);
    // The same flag with the face missing from a neighbouring cell: falls through.
    const OccluderList lit;  // no entry for the light
    const VertexLight fell = illuminateVertex(scene, 0, p, c.normal, c.normal, {&a, &lit});
    EXPECT_EQ(fell.decidedBy(), VertexCase::Unoccluded);
    ++done;
  }
  EXPECT_GT(done, 0u);
}

// ---- The one-sided limit ---------------------------------------------------------

// err(δ) = |limit − reference(p + δd)| must shrink about linearly with δ.
void expectLinearApproach(const Scene& scene, const ExactReference& reference, double peak,
                          const Vec3& p, const Vec3& n, const Vec3& d, const OccluderList& cell,
                          const std::array<double, 3>& deltas, const char* what) {
  const VertexIrradiance limit = illuminatePointFromCell(scene, p, n, n, d, cell);
  std::array<double, 3> err{};
  for (size_t i = 0; i < 3; ++i)
    err[i] = maxAbs(limit.irradiance - reference.evaluate(p + deltas[i] * d, n).irradiance);
  const double floor = 1e-12 * peak;
  for (size_t i = 1; i < 3; ++i) {
    // Linear: err ∝ δ; allow a factor 3 of curvature, never growth.
    const double allowed = 3 * err[i - 1] * deltas[i] / deltas[i - 1] + floor;
    EXPECT_LE(err[i], allowed) << what << " δ=" << deltas[i] << " err " << err[0] << " "
                               << err[1] << " " << err[2];
  }
}

TEST(IlluminateVertexFromCell, D0LimitsMatchReferenceApproach) {
  size_t sides = 0, corners = 0;
  for (int k = 0; k < 40; ++k) {
    // At most 6 cubes: the room stays small enough that δ = 1e-5 is beyond onPlane().
    const Scene scene = makeCubesScene(sceneOptions(k, 6));
    ASSERT_LT(scene.tolerance().onPlane(), 1e-5);
    const ExactReference reference(scene);
    const double peak = peakIrradiance(scene);
    std::mt19937_64 rng(900 + k);
    for (const Contact& c : contactsOf(scene, rng)) {
      for (const Vec3& d : {c.inside, -c.inside}) {
        OccluderList cell;
        for (size_t l = 0; l < scene.lights().size(); ++l) {
          std::vector<FaceId> faces = blockersNear(scene, l, c, d, {1e-5, 1e-4, 1e-3});
          if (glm::dot(d, c.inside) > 0) faces = unite(faces, facesOfObject(scene, c.object));
          appendEntries(cell, uint32_t(l), faces);  // no umbra flags: the limit geometry decides
        }
        expectLinearApproach(scene, reference, peak, c.p, c.normal, d, cell, {1e-3, 1e-4, 1e-5},
                             "edge");
        ++sides;
      }
      // The contact's corner, approached along the diagonal (inside and outside);
      // the smallest δ keeps p + δd beyond onPlane() of both side faces.
      const Vec3 a = c.side->polygon[0];
      for (const Face& other : scene.faces()) {
        if (other.id.object != c.object || &other == c.side || std::abs(other.plane.normal.y) > 1e-12) continue;
        if (std::abs(other.plane.signedDistance(a)) > scene.tolerance().length()) continue;
        if (std::abs(a.y - c.p.y) > scene.tolerance().length()) continue;
        const Vec3 diagonal = glm::normalize(-c.side->plane.normal - other.plane.normal);
        for (const Vec3& d : {diagonal, -diagonal}) {
          OccluderList cell;
          for (size_t l = 0; l < scene.lights().size(); ++l) {
            std::vector<FaceId> faces = blockersOf(scene, l, a, c.normal);
            for (double delta : {3e-5, 1e-4, 1e-3})
              faces = unite(faces, blockersOf(scene, l, a + delta * d, c.normal));
            if (glm::dot(d, diagonal) > 0) faces = unite(faces, facesOfObject(scene, c.object));
            appendEntries(cell, uint32_t(l), faces);
          }
          expectLinearApproach(scene, reference, peak, a, c.normal, d, cell, {1e-3, 1e-4, 3e-5},
                               "corner");
          ++corners;
        }
      }
      if (HasFailure()) return;
    }
  }
  std::printf("[illum] one-sided limits checked: %zu edge sides, %zu corner sides\n", sides, corners);
  EXPECT_GT(sides, 50u);
  EXPECT_GT(corners, 10u);
}

// A single tilted panel standing on the floor: from behind, at its corner, only part
// of the light is hidden in the limit (the light straddles the panel's side edge).
TEST(IlluminateVertexFromCell, TiltedPanelCornerHidesPartOfTheLight) {
  Light light;
  light.id = "light";
  light.polygon = {{-0.5, 2.5, -0.5}, {0.5, 2.5, -0.5}, {0.5, 2.5, 0.5}, {-0.5, 2.5, 0.5}};
  if (glm::dot(newellVector(light.polygon), Vec3(0, -1, 0)) < 0)
    std::reverse(light.polygon.begin(), light.polygon.end());
  light.radiance = Vec3(10);
  Object floor;
  floor.id = "floor";
  floor.vertices = {{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}};
  floor.faces = {{0, 1, 2, 3}};
  Object panel;
  panel.id = "panel";
  // Bottom edge on the floor at z = 0.3 from x = 0 to 1, leaning back to z = 0.7;
  // its front faces the light (−z and up).
  panel.vertices = {{0, 0, 0.3}, {0, 1, 0.7}, {1, 1, 0.7}, {1, 0, 0.3}};
  panel.faces = {{0, 1, 2, 3}};
  const Scene scene({light}, {}, {floor, panel});
  const Face& face = scene.faces()[1];
  ASSERT_GT(face.plane.normal.y, 0);
  ASSERT_LT(face.plane.normal.z, 0);
  // δ = 1e-5 with |n·d| ≥ 0.928 sin 60° keeps p + δd beyond onPlane() of the panel.
  ASSERT_LT(scene.tolerance().onPlane(), 1e-5 * 0.928 * std::sin(glm::radians(60.0)));
  const ExactReference reference(scene);
  const double peak = peakIrradiance(scene);
  const Vec3 n(0, 1, 0);
  OccluderList cell;
  appendEntries(cell, 0, {face.id});
  size_t partial = 0;
  for (const Vec3& p : {Vec3(0, 0, 0.3), Vec3(0.5, 0, 0.3), Vec3(1, 0, 0.3)}) {
    for (double deg : {60.0, 75.0, 90.0, 105.0, 120.0}) {
      const Vec3 d(std::cos(glm::radians(deg)), 0, std::sin(glm::radians(deg)));  // behind
      expectLinearApproach(scene, reference, peak, p, n, d, cell, {1e-3, 1e-4, 1e-5}, "panel");
      // Some corner limits are strictly partial (the side edge's constraint matters).
      const VertexLight lim = illuminateVertexFromCell(scene, 0, p, n, n, d, cell);
      if (p.x != 0.5 && lim.lightClass() == LightClass::Penumbra && lim.factor() > 0) ++partial;
      // From the front the panel does not block.
      const VertexLight front = illuminateVertexFromCell(scene, 0, p, n, n, -d, cell);
      EXPECT_EQ(front.lightClass(), LightClass::Lit);
      EXPECT_EQ(front.comparisons(), 0u);
    }
  }
  EXPECT_GE(partial, 3u);
}

// Time per vertex, case 3 with the true set, against the brute-force reference.
TEST(IlluminateVertex, TimePerVertexOnFifteenCubes) {
  CubesSceneOptions options;
  options.cubes = 15;
  options.seed = 42;
  const Scene scene = makeCubesScene(options);
  const ExactReference reference(scene);
  std::mt19937_64 rng(5);
  const Face& floor = scene.faces()[0];
  std::vector<Vec3> points;
  std::vector<OccluderList> cells;
  for (int i = 0; i < 2000; ++i) {
    points.push_back(randomPointOn(floor, rng));
    cells.emplace_back();
    appendEntries(cells.back(), 0, blockersOf(scene, 0, points.back(), floor.plane.normal));
  }
  using Clock = std::chrono::steady_clock;
  double sink = 0;
  const auto t0 = Clock::now();
  for (size_t i = 0; i < points.size(); ++i)
    sink += illuminatePoint(scene, points[i], floor.plane.normal, floor.plane.normal, {&cells[i]}).irradiance.x;
  const auto t1 = Clock::now();
  for (const Vec3& p : points) sink -= reference.evaluate(p, floor.plane.normal).irradiance.x;
  const auto t2 = Clock::now();
  const double mine = std::chrono::duration<double, std::micro>(t1 - t0).count() / points.size();
  const double ref = std::chrono::duration<double, std::micro>(t2 - t1).count() / points.size();
  std::printf("[illum] 15 cubes (%zu faces): %.2f us per vertex vs %.2f us reference (sum diff %.3g)\n",
              scene.faces().size(), mine, ref, sink);
  EXPECT_NEAR(sink, 0.0, 1e-9 * points.size());
}

}  // namespace
}  // namespace penumbra
