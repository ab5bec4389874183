// The engine's build and meshing give the same result on any number of threads: seeded
// generated scenes (one and two lights, tables, small lights) built with 1 and 2 threads
// (EngineSettings::threads) hold byte-identical trees, vertex values, per-light values,
// counters and meshes — also after an edit frame and a re-mesh of the changed receivers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "core/engine/engine.h"
#include "scenegen/cubes_scene.h"

namespace penumbra {
namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr uint64_t kThreadScenes = 2;
#else
constexpr uint64_t kThreadScenes = 3;
#endif

// The same bytes (not only equal values: -0 and +0 differ).
template <class T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}
bool sameBytes(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof(Vec3)) == 0; }

std::string meshDifference(const Mesh& a, const Mesh& b) {
  if (a.receivers.size() != b.receivers.size()) return "receiver count";
  for (size_t i = 0; i < a.receivers.size(); ++i) {
    const ReceiverMesh &x = a.receivers[i], &y = b.receivers[i];
    const std::string at = " of receiver " + std::to_string(i);
    if (!(x.face == y.face) || !sameBytes(x.normal, y.normal)) return "face" + at;
    if (!sameBytes(x.positions, y.positions)) return "positions" + at;
    if (!sameBytes(x.irradiance, y.irradiance)) return "irradiance" + at;
    if (!sameBytes(x.classes, y.classes)) return "classes" + at;
    if (!sameBytes(x.triangles, y.triangles)) return "triangles" + at;
  }
  return "";
}

// Every receiver's tree (vertex positions, cells) and every live vertex's value, byte for byte.
std::string engineDifference(const Engine& a, const Engine& b) {
  if (a.receivers().size() != b.receivers().size()) return "receiver count";
  for (size_t i = 0; i < a.receivers().size(); ++i) {
    const Engine::Receiver &x = a.receivers()[i], &y = b.receivers()[i];
    const std::string at = " of receiver " + std::to_string(i);
    if (!(x.face == y.face)) return "face" + at;
    if (x.tree.vertices() != y.tree.vertices() || x.tree.cellCount() != y.tree.cellCount() ||
        x.tree.internalNodeCount() != y.tree.internalNodeCount())
      return "tree shape" + at;
    for (VertexId v : x.tree.vertices()) {
      const Vec2 p = x.tree.position(v), q = y.tree.position(v);
      if (std::memcmp(&p, &q, sizeof(Vec2))) return "vertex position" + at;
      const VertexIrradiance s = a.value(x, v), t = b.value(y, v);
      if (!sameBytes(s.irradiance, t.irradiance) || s.lightClass != t.lightClass || s.comparisons != t.comparisons)
        return "vertex value" + at;
      const auto &ls = x.perLight[v.index], &lt = y.perLight[v.index];
      if (ls.size() != lt.size()) return "per-light count" + at;
      for (size_t l = 0; l < ls.size(); ++l) {
        const double fs = ls[l].factor(), ft = lt[l].factor();
        if (std::memcmp(&fs, &ft, sizeof(double)) || ls[l].lightClass() != lt[l].lightClass() ||
            ls[l].decidedBy() != lt[l].decidedBy() || ls[l].comparisons() != lt[l].comparisons())
          return "per-light value" + at;
      }
    }
    for (VertexId v : x.tree.vertices())
      for (CellId c : x.tree.cellsAround(v))
        if (!(x.tree.occluders(c) == y.tree.occluders(c))) return "occluder list" + at;
  }
  return "";
}

std::string countersDifference(const BuildStats& a, const BuildStats& b) {
  if (a.candidatePairs != b.candidatePairs || a.closedConvexPairs != b.closedConvexPairs || a.castAttempts != b.castAttempts ||
      a.pairsWithShadow != b.pairsWithShadow || a.tiles != b.tiles || a.orderFragments != b.orderFragments)
    return "casting counters";
  if (a.treeNodes != b.treeNodes || a.cells != b.cells || a.vertices != b.vertices ||
      a.litVertices != b.litVertices || a.penumbraVertices != b.penumbraVertices ||
      a.umbraVertices != b.umbraVertices || a.comparisons != b.comparisons)
    return "tree counters";
  return "";
}

CubesSceneOptions sceneOptions(uint64_t seed) {
  std::mt19937_64 random(seed);
  CubesSceneOptions options;
  options.seed = seed;
  options.cubes = 6 + int(random() % 9);
  options.twoLights = seed % 2 == 1;
  options.lightScale = seed % 3 == 2 ? 0.2 : 1.0;
  options.tiltedLight = seed % 4 == 3;
  options.thinTables = seed % 3 == 0 ? 0.3 : 0.0;
  return options;
}

Engine engineOn(const Scene& scene, int threads) {
  EngineSettings settings;
  settings.threads = threads;
  return Engine(scene, settings);
}

TEST(ThreadCount, OneAndTwoThreadsBuildAndMeshTheSameBytes) {
  for (uint64_t seed = 1; seed <= kThreadScenes; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Scene scene = makeCubesScene(sceneOptions(seed));
    Engine one = engineOn(scene, 1), two = engineOn(scene, 2);
    EXPECT_EQ(countersDifference(one.stats(), two.stats()), "");
    EXPECT_EQ(engineDifference(one, two), "");
    EXPECT_EQ(meshDifference(one.mesh(), two.mesh()), "");
    EXPECT_EQ(one.lastMeshCounters().cellsLit, two.lastMeshCounters().cellsLit);
    two.validate();
  }
}

TEST(ThreadCount, AFrameAndARemeshOfItsReceiversAgreeAcrossThreadCounts) {
  for (uint64_t seed = 1; seed <= kThreadScenes; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Scene scene = makeCubesScene(sceneOptions(seed));
    Engine one = engineOn(scene, 1), two = engineOn(scene, 2);
    one.mesh();
    two.mesh();
    // Move the first movable object (a cube or table) 5 cm along x.
    const auto movable = std::find_if(scene.objects().begin(), scene.objects().end(),
                                      [](const Object& o) { return !o.isStatic; });
    ASSERT_NE(movable, scene.objects().end());
    Edit move;
    move.op = Edit::Op::Move;
    move.id = movable->id;
    move.transform = movable->transform;
    move.transform.translate.x += 0.05;
    const Frame frame{{move}};
    const FrameResult a = one.apply(frame), b = two.apply(frame);
    EXPECT_EQ(a.changedReceivers, b.changedReceivers);
    EXPECT_EQ(engineDifference(one, two), "");
    EXPECT_EQ(meshDifference(one.mesh(a.changedReceivers), two.mesh(b.changedReceivers)), "");
    EXPECT_EQ(one.lastMeshCounters().cellsLit, two.lastMeshCounters().cellsLit);
    EXPECT_EQ(one.lastMeshCounters().cellsReused, two.lastMeshCounters().cellsReused);
  }
}

TEST(ThreadCount, ZeroMeansEveryCoreAndStillMatchesOneThread) {
  const Scene scene = makeCubesScene(sceneOptions(2));
  Engine one = engineOn(scene, 1), all = engineOn(scene, 0);
  EXPECT_EQ(engineDifference(one, all), "");
  EXPECT_EQ(meshDifference(one.mesh(), all.mesh()), "");
}

}  // namespace
}  // namespace penumbra
