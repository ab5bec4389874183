// Occluder-list soundness at the DM vertices, independent of how the vertex value
// is then computed: every face that hides positive light from a vertex is listed in
// some cell around it (else §2.4's O_covering would miss a blocker), unless one listed
// occluder alone hides the whole light there (umbra culling, DmTree::insert), and the
// value from those lists does not depend on the order the faces are subtracted in.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/engine/engine.h"
#include "core/illum/backprojection.h"
#include "protocol/scene_json.h"
#include "scenegen/cubes_scene.h"

namespace penumbra {
namespace {

struct Counts {
  size_t vertices = 0, missing = 0, orderDependent = 0;
  size_t culled = 0;  // blockers missing where a listed occluder alone hides the whole light
};

// Whether one occluder listed for light l hides the whole light from p by itself.
bool wholeLightHidden(const Scene& s, size_t l, const Vec3& p, const Vec3& n, const OccluderList& all, double full) {
  return std::any_of(all.begin(), all.end(), [&](const OccluderEntry& e) {
    if (e.light != l) return false;
    Backprojection alone(s, l, p, n);
    alone.occludeId(e.face);
    return alone.visibleFactor() <= 1e-12 * full;
  });
}

Counts checkLists(const Engine& engine) {
  const Scene& s = engine.scene();
  Counts counts;
  double peak = 0;  // the scale of invariant 1's absolute term
  for (const Engine::Receiver& r : engine.receivers())
    for (VertexId v : r.tree.vertices()) peak = std::max(peak, engine.value(r, v).irradiance.x);
  for (const Engine::Receiver& receiver : engine.receivers()) {
    for (VertexId v : receiver.tree.vertices()) {
      ++counts.vertices;
      const Vec3 p = receiver.frame.to3D(receiver.tree.position(v));
      const Vec3 n = receiver.frame.normal;
      const auto cells = receiver.tree.cellsAround(v);
      OccluderList all;  // the union of the lists around v, each (light, face) once
      for (CellId c : cells)
        for (const OccluderEntry& e : receiver.tree.occluders(c))
          if (std::none_of(all.begin(), all.end(),
                           [&](const OccluderEntry& x) { return x.light == e.light && x.face == e.face; }))
            all.push_back({e.light, e.face, false});

      for (size_t l = 0; l < s.lights().size(); ++l) {
        const Backprojection unblocked(s, l, p, n);
        if (!unblocked.applies()) continue;
        const double full = unblocked.visibleFactor();
        // Each face alone: does it hide positive light from p?
        for (const Face& f : s.faces()) {
          Backprojection one(s, l, p, n);
          if (!one.occlude(f)) continue;
          if (!(full - one.visibleFactor() > 1e-12 * full)) continue;
          // Listed itself, or its closed convex object cast whole (object_shadow.h).
          const bool listed = std::any_of(all.begin(), all.end(), [&](const OccluderEntry& e) {
            return e.light == l && (e.face == f.id || e.face == wholeObject(f.id.object));
          });
          if (listed) continue;
          if (wholeLightHidden(s, l, p, n, all, full)) {
            ++counts.culled;
            continue;
          }
          if (counts.missing++ < 5)
            ADD_FAILURE() << "receiver " << receiver.face.object << "/" << receiver.face.face << " vertex "
                          << v.index << " light " << l << ": face " << f.id.object << "/" << f.id.face
                          << " hides " << full - one.visibleFactor() << " of " << full
                          << " but is in no cell around the vertex";
        }
      }
      // The same candidate faces in opposite orders give the same value (to invariant
      // 1's tolerance: an order-dependent cut is how a correct list gave a wrong value).
      std::sort(all.begin(), all.end(), [](const OccluderEntry& a, const OccluderEntry& b) {
        return std::tie(a.light, a.face) < std::tie(b.light, b.face);
      });
      const Vec3 forward = illuminatePoint(s, p, n, n, {&all}).irradiance;
      std::reverse(all.begin(), all.end());
      const Vec3 backward = illuminatePoint(s, p, n, n, {&all}).irradiance;
      for (int c = 0; c < 3; ++c)
        if (std::abs(forward[c] - backward[c]) > 1e-9 * std::abs(forward[c]) + 1e-12 * peak) {
          if (counts.orderDependent++ < 5)
            ADD_FAILURE() << "receiver " << receiver.face.object << "/" << receiver.face.face << " vertex "
                          << v.index << ": order-dependent backprojection " << forward[c] << " vs "
                          << backward[c];
          break;
        }
    }
  }
  return counts;
}

TEST(OccluderLists, OfficeListsEveryBlockerAroundEveryVertex) {
  const Engine engine(
      protocol::loadSceneFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/office.scene.json"));
  const Counts c = checkLists(engine);
  std::printf("office: %zu vertices, %zu missing blockers, %zu order-dependent, %zu culled in an umbra\n",
              c.vertices, c.missing, c.orderDependent, c.culled);
  EXPECT_EQ(c.missing, 0u);
  EXPECT_EQ(c.orderDependent, 0u);
}

TEST(OccluderLists, GeneratedScenesListEveryBlockerAroundEveryVertex) {
  Counts total;
  for (uint64_t seed = 1; seed <= 40; ++seed) {
    const CubesSceneOptions options = mixedCubesOptions(seed);
    SCOPED_TRACE(seed);
    const Engine engine(makeCubesScene(options));
    const Counts c = checkLists(engine);
    total.vertices += c.vertices;
    total.missing += c.missing;
    total.orderDependent += c.orderDependent;
    total.culled += c.culled;
  }
  std::printf("generated: %zu vertices, %zu missing blockers, %zu order-dependent, %zu culled in an umbra\n",
              total.vertices, total.missing, total.orderDependent, total.culled);
  EXPECT_EQ(total.missing, 0u);
  EXPECT_EQ(total.orderDependent, 0u);
}

}  // namespace
}  // namespace penumbra
