// Engine::compactTrees: over seeded drags that go back and forth (a person dragging for a
// long time), receivers' DM-trees stay within kCompactSlotRatio × their live slots, a tree
// cast afresh meshes exactly as a fresh engine's, and without compaction the slots grow.
#include <gtest/gtest.h>

#include "bench/lib/cubes_scene.h"
#include "bench/lib/edit_scripts.h"
#include "core/engine/engine.h"

namespace penumbra {
namespace {

size_t totalSlots(const Engine& engine) {
  size_t n = 0;
  for (const Engine::Receiver& r : engine.receivers()) n += r.tree.nodeSlots();
  return n;
}

bool sameMesh(const ReceiverMesh& a, const ReceiverMesh& b) {
  return a.normal == b.normal && a.positions == b.positions && a.irradiance == b.irradiance &&
         a.classes == b.classes && a.triangles == b.triangles;
}

// The drag out and back, `rounds` times.
std::vector<Frame> backAndForth(const Scene& scene, uint64_t seed, int rounds) {
  const EditScript drag = dragScript(scene, 24, seed);
  std::vector<Frame> frames;
  for (int r = 0; r < rounds; ++r) {
    frames.insert(frames.end(), drag.frames.begin(), drag.frames.end());
    frames.insert(frames.end(), drag.frames.rbegin(), drag.frames.rend());
  }
  return frames;
}

TEST(TreeCompaction, SlotsStayBoundedAndCompactedTreesMeshAsFresh) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    CubesSceneOptions options;
    options.seed = seed;
    const Scene scene = makeCubesScene(options);
    Engine compacted(scene), growing(scene);
    size_t casts = 0;
    for (const Frame& frame : backAndForth(scene, seed, 4)) {
      const FrameResult result = compacted.apply(frame);
      growing.apply(frame);
      const std::vector<FaceId> fresh = compacted.compactTrees(result.changedReceivers);
      casts += fresh.size();
      if (fresh.empty()) continue;
      // A tree cast afresh is the tree a fresh engine builds for the same scene.
      Engine reference(compacted.scene());
      for (FaceId face : fresh)
        EXPECT_TRUE(sameMesh(compacted.meshOf(face), reference.meshOf(face)))
            << "object " << face.object << " face " << face.face;
    }
    EXPECT_GT(casts, 0u);
    compacted.validate();
    for (const Engine::Receiver& r : compacted.receivers())
      EXPECT_LE(r.tree.nodeSlots(),
                std::max<size_t>(1024, Engine::kCompactSlotRatio * r.tree.nodeCount()) + 64)
          << "object " << r.face.object << " face " << r.face.face;
    // Without compaction the same frames leave more slots behind.
    EXPECT_GT(totalSlots(growing), totalSlots(compacted));
  }
}

}  // namespace
}  // namespace penumbra
