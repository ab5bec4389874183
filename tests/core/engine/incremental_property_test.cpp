// Incremental edits against full rebuilds (DESIGN.md invariants 3 and 4) over
// seeded random frames on generated cube scenes: after every frame the engine
// equals Engine(engine.scene()) — vertex values at the same points, class at random
// points, discontinuity segments up to splitting — and every vertex whose value
// changed was relit, with the relit count reported against the changed count. A
// second sweep mixes in light edits (set_light, add_light, remove_light).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>

#include "core/engine/engine.h"
#include "core/engine/light_edits.h"
#include "core/reference/exact_irradiance.h"
#include "scenegen/cubes_scene.h"
#include "tests/core/engine/incremental_compare.h"

namespace penumbra {
namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr size_t kIncrementalScenes = 8;  // sanitizer builds run ~10x slower: a smaller sweep
#else
constexpr size_t kIncrementalScenes = 40;
#endif
constexpr size_t kEditsPerScene = 26;
#if defined(__SANITIZE_ADDRESS__)
constexpr size_t kLightScenes = 3;
#else
constexpr size_t kLightScenes = 12;
#endif
constexpr size_t kFramesPerLightScene = 9;

struct Snapshot {
  Vec2 position;
  VertexIrradiance value;
};
using Snapshots = std::map<FaceId, std::map<uint32_t, Snapshot>>;

Snapshots snapshot(const Engine& engine) {
  Snapshots out;
  for (const auto& r : engine.receivers())
    for (VertexId v : r.tree.vertices()) out[r.face][v.index] = {r.tree.position(v), engine.value(r, v)};
  return out;
}

// The checks after each frame (invariants 1, 3, 4) and their totals over a sweep.
struct Tally {
  size_t edits = 0, frames = 0, relit = 0, changed = 0, created = 0, observedChanged = 0, rebuilds = 0;
  size_t unsound = 0, untouchedRelit = 0, mismatchedFrames = 0, referenceErrors = 0, referenceChecks = 0;
  size_t compared = 0, matched = 0, segmentSamples = 0, points = 0, nodesDeleted = 0, rebuildOff = 0;
  size_t fullRebuilds = 0;
  double worstRatio = 0;

  void check(const Engine& engine, const Frame& frame, const FrameResult& result, const Snapshots& before,
             uint64_t seed) {
    edits += frame.edits.size();
    ++frames;
    SCOPED_TRACE("frame " + std::to_string(frames));
    ASSERT_NO_THROW(engine.validate());
    relit += result.verticesRelit;
    changed += result.verticesChanged;
    created += result.verticesCreated;
    rebuilds += result.treeRebuilds;
    nodesDeleted += result.nodesDeleted;
    fullRebuilds += result.fullRebuild;
    if (result.verticesChanged > 0)
      worstRatio = std::max(worstRatio, double(result.verticesRelit) / double(result.verticesChanged));
    checkRelit(engine, frame, result, before);

    // Invariant 3: equal to a full rebuild of the resulting scene.
    const Engine rebuilt(engine.scene());
    const double peak = std::max(testing::peakIrradiance(rebuilt), 1e-300);
    const testing::EngineDiff diff = testing::compareEngines(engine, rebuilt, peak, 40, seed * 1000 + frames);
    compared += diff.vertices;
    rebuildOff += diff.secondOffReference;
    matched += diff.matchedVertices;
    segmentSamples += diff.segmentSamples;
    points += diff.pointsCompared;
    if (diff.errors()) {
      if (mismatchedFrames++ < 5)
        ADD_FAILURE() << diff.valueErrors << " value, " << diff.classErrors << " class, " << diff.segmentErrors
                      << " segment, " << diff.receiverErrors << " receiver errors; first: " << diff.firstProblem;
    }
    checkReference(engine, peak);
  }

  // Invariant 4: a surviving vertex whose value changed was relit; one not relit kept its
  // value bit for bit; receivers not reported changed relit nothing.
  void checkRelit(const Engine& engine, const Frame& frame, const FrameResult& result, const Snapshots& before) {
    const auto& relitSets = engine.lastRelit();
    std::set<uint32_t> moved;  // their receivers are new trees (same ids, frame-relative points)
    for (const Edit& edit : frame.edits)
      if (const auto index = engine.scene().findObject(edit.id); edit.op == Edit::Op::Move && index)
        moved.insert(engine.scene().handleOf(*index));
    for (const auto& r : engine.receivers()) {
      const auto old = before.find(r.face);
      const auto relitHere = relitSets.find(r.face);
      const bool reported = std::binary_search(result.changedReceivers.begin(), result.changedReceivers.end(), r.face);
      if (relitHere != relitSets.end() && !reported) ++untouchedRelit;
      if (old == before.end() || moved.count(r.face.object)) continue;
      for (VertexId v : r.tree.vertices()) {
        const auto was = old->second.find(v.index);
        if (was == old->second.end() || was->second.position != r.tree.position(v)) continue;
        const bool isRelit = relitHere != relitSets.end() &&
                             std::binary_search(relitHere->second.begin(), relitHere->second.end(), v);
        // A full rebuild reports every vertex created (changed − created = 0): not counted.
        if (!result.fullRebuild && !sameValue(was->second.value, engine.value(r, v))) ++observedChanged;
        if (!isRelit && !identicalValue(was->second.value, engine.value(r, v))) ++unsound;
      }
    }
  }

  // Invariant 1 on a few relit vertices: the independent exact reference.
  void checkReference(const Engine& engine, double peak) {
    const ExactReference reference(engine.scene());
    size_t checked = 0;
    for (const auto& [face, vertices] : engine.lastRelit()) {
      const Engine::Receiver* r = engine.receiver(face);
      for (size_t i = 0; i < vertices.size() && checked < 6; i += 1 + vertices.size() / 3, ++checked) {
        const VertexId v = vertices[i];
        const PointIrradiance truth = reference.evaluate(r->frame.to3D(r->tree.position(v)), r->frame.normal);
        ++referenceChecks;
        for (int c = 0; c < 3; ++c)
          if (std::abs(engine.value(*r, v).irradiance[c] - truth.irradiance[c]) >
              1e-9 * std::abs(truth.irradiance[c]) + 1e-12 * peak) {
            if (referenceErrors++ < 5)
              ADD_FAILURE() << "relit vertex of " << face.object << "/" << face.face << ": "
                            << engine.value(*r, v).irradiance[c] << " vs reference " << truth.irradiance[c];
            break;
          }
      }
    }
  }

  void print() const {
    std::printf("%zu edits in %zu frames: %zu vertices relit, %zu changed (reported), %zu changed (observed on "
                "survivors), %zu created; relit/changed %.2f overall, worst frame %.2f; %zu nodes deleted; "
                "%zu tree rebuilds (fallback); %zu full rebuilds\n",
                edits, frames, relit, changed, observedChanged, created,
                changed ? double(relit) / double(changed) : 0.0, worstRatio, nodesDeleted, rebuilds, fullRebuilds);
    std::printf("compared %zu vertices (%zu at a vertex of the other engine), %zu segment samples, %zu random "
                "points, %zu reference checks; %zu vertices where the rebuild is off the exact reference and "
                "the incremental engine is not\n",
                compared, matched, segmentSamples, points, referenceChecks, rebuildOff);
  }

  void expectSound() const {
    EXPECT_EQ(unsound, 0u) << "vertices whose value changed without being relit";
    EXPECT_EQ(untouchedRelit, 0u) << "receivers relit but not reported changed";
    EXPECT_EQ(mismatchedFrames, 0u);
    EXPECT_EQ(referenceErrors, 0u);
    // Backprojection subtracts faces in FaceId order, so the two engines agree even
    // where the covering faces were listed in different orders.
    EXPECT_EQ(rebuildOff, 0u) << "incremental and rebuilt values differ";
    EXPECT_LE(observedChanged, changed - created);
  }
};

TEST(IncrementalProperty, EditsEqualRebuildAndRelightSoundly) {
  Tally tally;
  for (uint64_t seed = 1; seed <= kIncrementalScenes; ++seed) {
    SCOPED_TRACE("scene seed " + std::to_string(seed));
    Engine engine(makeCubesScene(mixedCubesOptions(seed)));
    std::mt19937_64 rng(seed * 7919);
    int nextNewId = 0;
    size_t sceneEdits = 0;
    while (sceneEdits < kEditsPerScene) {
      const size_t count = std::uniform_int_distribution<size_t>(1, 3)(rng);
      const Frame frame = testing::randomFrame(engine, rng, count, nextNewId);
      const Snapshots before = snapshot(engine);
      const FrameResult result = engine.apply(frame);
      sceneEdits += count;
      tally.check(engine, frame, result, before, seed);
    }
  }
  tally.print();
  EXPECT_GE(tally.edits, kIncrementalScenes * kEditsPerScene);
  tally.expectSound();
  EXPECT_LE(tally.relit, 20 * tally.changed) << "relighting far more than what changes";
}

// The same with light edits mixed in (set_light, add_light, remove_light, with object edits
// in the same frame or the next): object frames after a light was added or removed run
// incrementally with the new set of lights and still equal a rebuild and the reference.
TEST(IncrementalProperty, LightEditsMixedInEqualRebuild) {
  Tally tally;
  size_t added = 0, removed = 0, maxLights = 0;
  for (uint64_t seed = 1; seed <= kLightScenes; ++seed) {
    SCOPED_TRACE("scene seed " + std::to_string(seed));
    Engine engine(makeCubesScene(mixedCubesOptions(seed)));
    std::mt19937_64 rng(seed * 104729);
    int nextNewId = 0, nextLightId = 0;
    for (size_t f = 0; f < kFramesPerLightScene; ++f) {
      const size_t count = std::uniform_int_distribution<size_t>(0, 2)(rng);
      const bool lightFrame = f % 3 == 0;
      const Frame frame = lightFrame ? testing::randomLightFrame(engine, rng, count, nextNewId, nextLightId)
                                     : testing::randomFrame(engine, rng, count + 1, nextNewId);
      for (const Edit& edit : frame.edits) {
        added += edit.op == Edit::Op::AddLight;
        removed += edit.op == Edit::Op::RemoveLight;
      }
      const Snapshots before = snapshot(engine);
      const FrameResult result = engine.apply(frame);
      if (reshapesLights(frame)) EXPECT_TRUE(result.fullRebuild);
      maxLights = std::max(maxLights, engine.scene().lights().size());
      tally.check(engine, frame, result, before, seed);
    }
  }
  tally.print();
  std::printf("%zu lights added, %zu removed, at most %zu lights in a scene\n", added, removed, maxLights);
  EXPECT_GT(added, 0u);
  EXPECT_GT(removed, 0u);
  EXPECT_GE(maxLights, 3u);
  tally.expectSound();
}

}  // namespace
}  // namespace penumbra
