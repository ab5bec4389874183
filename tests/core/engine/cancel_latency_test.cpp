// A cancel (the progress callback throwing) lands within a bound that does not grow with one
// receiver's size: the floor of 150 seeded cubes is one receiver holding most of the display
// meshing (seconds), and a cancel while it is being meshed reaches the caller within a small
// fraction of the floor's own meshing time, since its meshing beats every few cells. Without the
// beats the cancel waited for the whole floor.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "core/engine/engine.h"
#include "scenegen/cubes_scene.h"

namespace penumbra {
namespace {

using Clock = std::chrono::steady_clock;

double secondsBetween(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled") {}
};

// The share of the largest receiver's meshing time a cancel may take to land.
constexpr double kLatencyShare = 0.1;
// The cancel comes this long into the meshing, when the floor's is well under way.
constexpr auto kCancelAfter = std::chrono::milliseconds(200);

TEST(CancelLatency, ACancelDuringTheLargestReceiversMeshingLandsWithinAFractionOfIt) {
  CubesSceneOptions cubes;
  cubes.cubes = 150;
  EngineSettings settings;
  settings.threads = 2;
  Engine engine(makeCubesScene(cubes), settings);
  const Engine::Receiver* largest = &engine.receivers().front();
  for (const Engine::Receiver& receiver : engine.receivers())
    if (receiver.tree.vertices().size() > largest->tree.vertices().size()) largest = &receiver;
  const FaceId largestFace = largest->face;

  // Cancelled once the meshing has run kCancelAfter: every later report throws too, as a job's
  // flag stays set.
  std::mutex mutex;
  const Clock::time_point start = Clock::now();
  std::optional<Clock::time_point> cancelledAt;
  const EngineProgress progress = [&](const char* step, size_t, size_t) {
    std::lock_guard lock(mutex);
    if (!cancelledAt && std::strcmp(step, "triangulation") == 0 && Clock::now() - start >= kCancelAfter)
      cancelledAt = Clock::now();
    if (cancelledAt) throw Cancelled();
  };
  std::optional<Clock::time_point> landed;
  try {
    engine.mesh(progress);
  } catch (const Cancelled&) {
    landed = Clock::now();
  }
  ASSERT_TRUE(cancelledAt) << "the meshing ended before the cancel";
  ASSERT_TRUE(landed);
  const double latency = secondsBetween(*cancelledAt, *landed);

  // The largest receiver's meshing alone, afresh (the cancelled memo dropped).
  engine.forgetMeshMemo();
  const Clock::time_point meshStart = Clock::now();
  const ReceiverMesh mesh = engine.meshOf(largestFace);
  const double largestSeconds = secondsBetween(meshStart, Clock::now());
  EXPECT_GT(mesh.triangles.size(), 100000u) << "not a large receiver";
  RecordProperty("latency_ms", int(latency * 1000));
  RecordProperty("largest_receiver_ms", int(largestSeconds * 1000));
  EXPECT_LT(latency, kLatencyShare * largestSeconds)
      << "the cancel took " << latency << " s to land; the largest receiver's meshing takes "
      << largestSeconds << " s";
}

}  // namespace
}  // namespace penumbra
