// Engine::compactTrees: over a seeded drag that goes back and forth (a person dragging for a
// long time), receivers' DM-trees stay within kCompactSlotRatio × their live slots (without
// compaction they grow), the engine validates, and the light is the same: at random points the
// compacted and the uncompacted engines' meshes interpolate to the same irradiance (their
// vertices carry exact values; only the cells, so the triangles between them, may differ).
#include <gtest/gtest.h>

#include "bench/lib/edit_scripts.h"
#include "bench/lib/mesh_sampling.h"
#include "bench/lib/sample_points.h"
#include "core/engine/engine.h"
#include "scenegen/cubes_scene.h"

namespace penumbra {
namespace {

size_t totalSlots(const Engine& engine) {
  size_t n = 0;
  for (const Engine::Receiver& r : engine.receivers()) n += r.tree.nodeSlots();
  return n;
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

TEST(TreeCompaction, SlotsStayBoundedAndLightStaysTheSame) {
  CubesSceneOptions options;
  options.seed = 3;
  const Scene scene = makeCubesScene(options);
  Engine compacted(scene), growing(scene);
  size_t casts = 0;
  for (const Frame& frame : backAndForth(scene, options.seed, 3)) {
    const FrameResult result = compacted.apply(frame);
    growing.apply(frame);
    casts += compacted.compactTrees(result.changedReceivers).size();
  }
  EXPECT_GT(casts, 0u);
  compacted.validate();
  for (const Engine::Receiver& r : compacted.receivers())
    EXPECT_LE(r.tree.nodeSlots(),
              std::max<size_t>(1024, Engine::kCompactSlotRatio * r.tree.nodeCount()) + 64)
        << "object " << r.face.object << " face " << r.face.face;
  EXPECT_GT(totalSlots(growing), totalSlots(compacted));

  const Mesh a = compacted.mesh(), b = growing.mesh();
  const MeshInterpolator atA(a), atB(b);
  double sumDiff = 0, sum = 0, worst = 0;
  size_t n = 0;
  for (const SurfacePoint& p : sampleReceivingPoints(compacted.scene(), 4000, 7)) {
    const auto va = atA.at(p.face, p.position), vb = atB.at(p.face, p.position);
    if (!va || !vb) continue;
    const double d = glm::length(*va - *vb), m = std::max(glm::length(*va), glm::length(*vb));
    sumDiff += d;
    sum += m;
    if (m > 0) worst = std::max(worst, d / m);
    ++n;
  }
  std::printf("[ compaction ] %zu trees cast afresh; slots %zu vs %zu uncompacted; %zu points: "
              "relative L1 difference %.2e, worst %.2e\n",
              casts, totalSlots(compacted), totalSlots(growing), n, sumDiff / sum, worst);
  EXPECT_GT(n, 3000u);
  EXPECT_LT(sumDiff / sum, 1e-3);
}

}  // namespace
}  // namespace penumbra
