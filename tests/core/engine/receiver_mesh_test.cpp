// Per-receiver meshing (Engine::meshOf, Engine::mesh(only)) and the per-cell mesh memo:
// over seeded random edit frames on generated cube scenes, a mesh kept up to date by
// re-meshing only FrameResult::changedReceivers (and new receivers) with a warm memo
// equals, bit for bit, a fresh mesh() of an engine given the same frames whose memo
// is dropped first; meshOf(face) equals that receiver's part of mesh().
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "core/engine/engine.h"
#include "scenegen/cubes_scene.h"
#include "tests/core/engine/incremental_compare.h"

namespace penumbra {
namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr uint64_t kScenes = 3;
#else
constexpr uint64_t kScenes = 12;
#endif
constexpr size_t kFramesPerScene = 10;

// Exact equality of every field (doubles compared bit for bit, NaN never equal).
std::string firstDifference(const ReceiverMesh& a, const ReceiverMesh& b) {
  if (!(a.face == b.face)) return "face";
  if (a.normal != b.normal) return "normal";
  if (a.positions != b.positions) return "positions";
  if (a.irradiance != b.irradiance) return "irradiance";
  if (a.classes != b.classes) return "classes";
  if (a.triangles != b.triangles) return "triangles";
  return "";
}

void expectSameMesh(const Mesh& got, const Mesh& want) {
  ASSERT_EQ(got.receivers.size(), want.receivers.size());
  for (size_t i = 0; i < got.receivers.size(); ++i)
    EXPECT_EQ(firstDifference(got.receivers[i], want.receivers[i]), "")
        << "receiver " << i << " (object " << want.receivers[i].face.object << " face "
        << want.receivers[i].face.face << ")";
}

// What the server does: re-mesh the changed and new receivers, keep the others.
Mesh updateKept(Engine& engine, const Mesh& kept, const FrameResult& result, size_t& meshed) {
  std::map<FaceId, const ReceiverMesh*> before;
  for (const ReceiverMesh& r : kept.receivers) before[r.face] = &r;
  const std::set<FaceId> changed(result.changedReceivers.begin(), result.changedReceivers.end());
  std::vector<FaceId> remesh;
  for (const auto& r : engine.receivers())
    if (changed.count(r.face) || !before.count(r.face)) remesh.push_back(r.face);
  meshed += remesh.size();
  Mesh fresh = engine.mesh(remesh);
  EXPECT_EQ(fresh.receivers.size(), remesh.size());
  Mesh out;
  size_t k = 0;
  for (const auto& r : engine.receivers()) {
    if (k < fresh.receivers.size() && fresh.receivers[k].face == r.face)
      out.receivers.push_back(std::move(fresh.receivers[k++]));
    else
      out.receivers.push_back(*before.at(r.face));
  }
  return out;
}

TEST(ReceiverMesh, KeptMeshWithWarmMemoEqualsFreshMeshAfterRandomEdits) {
  size_t frames = 0, meshed = 0, receivers = 0, reused = 0, lit = 0;
  for (uint64_t seed = 1; seed <= kScenes; ++seed) {
    SCOPED_TRACE("scene seed " + std::to_string(seed));
    const Scene scene = makeCubesScene(mixedCubesOptions(seed));
    Engine warm(scene), fresh(scene);
    Mesh kept = warm.mesh();
    std::mt19937_64 rng(seed * 104729);
    int nextNewId = 0, nextNewIdFresh = 0;
    for (size_t f = 0; f < kFramesPerScene; ++f) {
      SCOPED_TRACE("frame " + std::to_string(f));
      const size_t count = std::uniform_int_distribution<size_t>(1, 3)(rng);
      std::mt19937_64 copy = rng;
      const Frame frame = testing::randomFrame(warm, rng, count, nextNewId);
      const Frame same = testing::randomFrame(fresh, copy, count, nextNewIdFresh);
      ASSERT_EQ(frame.edits.size(), same.edits.size());
      const FrameResult result = warm.apply(frame);
      fresh.apply(same);
      ++frames;

      kept = updateKept(warm, kept, result, meshed);
      reused += warm.lastMeshCounters().cellsReused;
      lit += warm.lastMeshCounters().cellsLit;
      receivers += warm.receivers().size();
      fresh.forgetMeshMemo();
      const Mesh whole = fresh.mesh();
      EXPECT_EQ(fresh.lastMeshCounters().cellsReused, 0u);
      expectSameMesh(kept, whole);
      if (f % 3 == 2) {
        // The warm engine's full mesh, and one receiver at a time.
        expectSameMesh(warm.mesh(), whole);
        for (const ReceiverMesh& r : whole.receivers)
          EXPECT_EQ(firstDifference(warm.meshOf(r.face), r), "");
      }
      if (::testing::Test::HasFailure()) return;
    }
  }
  std::printf("[ receiver mesh ] %zu frames: %zu of %zu receivers re-meshed; cells reused %zu, lit %zu\n",
              frames, meshed, receivers, reused, lit);
  // The memo is used (these frames are large edits of small scenes: most cells of
  // a changed receiver change; a drag reuses far more, see tests/server), and
  // re-meshing is selective.
  EXPECT_GT(reused, 0u);
  EXPECT_LT(meshed, receivers);
}

TEST(ReceiverMesh, OnlyListedReceiversInSceneOrder) {
  Engine engine(makeCubesScene(mixedCubesOptions(3)));
  const Mesh whole = engine.mesh();
  ASSERT_GE(whole.receivers.size(), 3u);
  const FaceId first = whole.receivers.front().face, last = whole.receivers.back().face;
  // Out of order, repeated, and a face that is not a receiver: scene order, once each.
  const Mesh some = engine.mesh({last, first, last, FaceId{999999, 0}});
  ASSERT_EQ(some.receivers.size(), 2u);
  EXPECT_EQ(firstDifference(some.receivers[0], whole.receivers.front()), "");
  EXPECT_EQ(firstDifference(some.receivers[1], whole.receivers.back()), "");
  EXPECT_TRUE(engine.mesh(std::vector<FaceId>{}).receivers.empty());
  EXPECT_THROW(engine.meshOf(FaceId{999999, 0}), std::out_of_range);
}

TEST(ReceiverMesh, MemoReplaysUnchangedCellsOnly) {
  Engine engine(makeCubesScene(mixedCubesOptions(5)));
  const Mesh first = engine.mesh();
  EXPECT_EQ(engine.lastMeshCounters().cellsReused, 0u);
  const size_t cells = engine.lastMeshCounters().cellsLit;
  const Mesh second = engine.mesh();
  // Nothing changed: every cell is replayed, and the result is the same.
  EXPECT_EQ(engine.lastMeshCounters().cellsLit, 0u);
  EXPECT_EQ(engine.lastMeshCounters().cellsReused, cells);
  expectSameMesh(second, first);
}

}  // namespace
}  // namespace penumbra
