// Tile placement (seed 001 Fig. 7) and the id-aware composition filter (Fig. 8), on synthetic
// images: smooth values need few sensors and come back exactly, edges are sensed, nothing
// mixes across surfaces.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <random>

#include "core/gi/id_filter.h"
#include "core/gi/sensor_placement.h"

namespace penumbra::gi {
namespace {

TEST(SensorPlacement, ALinearFieldOnOneSurfaceIsSensedAtTheFirstCornersOnly) {
  const int w = 67, h = 45;  // not multiples of the tile
  const std::vector<int32_t> id(size_t(w) * h, 3);
  auto field = [&](size_t p) { return Vec3(1 + 0.01 * double(p % w), 2 + 0.02 * double(p / w), 1.0); };
  std::atomic<size_t> calls{0};
  PlacementStats stats;
  const auto values = placeSensors(w, h, id, [&](size_t p) { ++calls; return field(p); }, {16, 0.5},
                                   Parallel(2), stats);
  EXPECT_EQ(stats.sensors, calls.load());
  // Corners at x = 0 16 32 48 64 66 and y = 0 16 32 44.
  EXPECT_EQ(stats.sensors, size_t(6 * 4));
  for (size_t p = 0; p < values.size(); ++p)
    ASSERT_NEAR(glm::length(values[p] - field(p)), 0.0, 1e-9) << p;  // bilinear is exact on a linear field
}

TEST(SensorPlacement, EdgesBetweenSurfacesAreSensedAndNeverInterpolatedAcross) {
  std::mt19937_64 rng(5);
  for (int round = 0; round < 20; ++round) {
    const int w = 20 + int(rng() % 60), h = 20 + int(rng() % 60), tile = 1 << (rng() % 5);
    // Two surfaces split by a random line, a hole (no surface) in a corner.
    const double a = double(rng() % 1000) / 1000 * w, b = double(rng() % 1000) / 1000 * h;
    std::vector<int32_t> id(size_t(w) * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) id[size_t(y) * w + x] = x < 4 && y < 4 ? -1 : (x / a + y / b < 1 ? 0 : 1);
    auto field = [&](size_t p) { return id[p] == 0 ? Vec3(1.0) : Vec3(100.0 + double(p % w)); };
    PlacementStats stats;
    const auto values = placeSensors(w, h, id, field, {tile, 0.05}, Parallel(1), stats);
    for (size_t p = 0; p < values.size(); ++p) {
      if (id[p] < 0) {
        ASSERT_EQ(values[p], Vec3(0.0));
        continue;
      }
      // Surface 0 is 1 everywhere; surface 1 is linear: any mixing shows.
      ASSERT_NEAR(glm::length(values[p] - field(p)), 0.0, 1e-9) << "round " << round << " pixel " << p;
    }
    EXPECT_LT(stats.sensors, values.size());
  }
}

TEST(SensorPlacement, AStepInsideOneSurfaceIsRefinedDownToPixels) {
  const int w = 64, h = 64;
  const std::vector<int32_t> id(size_t(w) * h, 0);
  auto field = [&](size_t p) { return Vec3(int(p % w) < 37 ? 1.0 : 2.0); };  // a shadow edge
  PlacementStats stats;
  const auto values = placeSensors(w, h, id, field, {16, 0.05}, Parallel(2), stats);
  for (size_t p = 0; p < values.size(); ++p) ASSERT_EQ(values[p], field(p)) << p;
  EXPECT_GT(stats.sensorsPerLevel.size(), 4u);
  EXPECT_LT(stats.sensors, values.size() / 4);
}

TEST(SensorPlacement, TheSameValuesOnOneAndTwoThreads) {
  const int w = 50, h = 40;
  std::vector<int32_t> id(size_t(w) * h);
  for (size_t p = 0; p < id.size(); ++p) id[p] = int32_t((p % w) / 13 + 2 * ((p / w) / 17));
  auto field = [&](size_t p) { return Vec3(std::sin(0.3 * double(p % w)) + 2, std::cos(0.2 * double(p / w)) + 2, 1); };
  PlacementStats one, two;
  EXPECT_EQ(placeSensors(w, h, id, field, {8, 0.02}, Parallel(1), one),
            placeSensors(w, h, id, field, {8, 0.02}, Parallel(2), two));
  EXPECT_EQ(one.sensors, two.sensors);
}

// A level can hold ~10⁵ sensors (seconds of work): reports come from inside it, counting up, so a
// render's cancel (a throw from the report) lands within a few dozen sensors, not at the level's end.
TEST(SensorPlacement, ReportsComeFromInsideALevelAndCountUp) {
  const int w = 161, h = 161;  // tile 2: the first level alone has 81² = 6,561 corners
  const std::vector<int32_t> id(size_t(w) * h, 0);
  auto field = [&](size_t p) { return Vec3(1 + 0.001 * double(p % w), 1.0, 1.0); };
  for (int threads : {1, 2}) {
    std::vector<size_t> reports;  // one call at a time: no lock needed
    PlacementStats stats;
    placeSensors(w, h, id, field, {2, 0.5}, Parallel(threads), stats, [&](size_t sensors) { reports.push_back(sensors); });
    ASSERT_EQ(stats.sensorsPerLevel.front(), size_t(81 * 81));
    ASSERT_FALSE(reports.empty());
    EXPECT_LT(reports.front(), stats.sensorsPerLevel.front() / 50) << threads << " threads: the first report";
    EXPECT_TRUE(std::is_sorted(reports.begin(), reports.end())) << threads << " threads";
    EXPECT_EQ(reports.back(), stats.sensors);
  }
}

TEST(SensorPlacement, AThrowFromTheReportEndsTheLevelItCameFrom) {
  const int w = 161, h = 161;
  const std::vector<int32_t> id(size_t(w) * h, 0);
  for (int threads : {1, 2}) {
    std::atomic<size_t> sensed{0};
    PlacementStats stats;
    EXPECT_THROW(placeSensors(w, h, id, [&](size_t) { ++sensed; return Vec3(1.0); }, {2, 0.5}, Parallel(threads), stats,
                              [](size_t) { throw std::runtime_error("cancelled"); }),
                 std::runtime_error);
    // The first report comes at 64 sensors; the other thread finishes at most its chunk.
    EXPECT_LT(sensed.load(), size_t(81 * 81) / 10) << threads << " threads";
  }
}

TEST(IdAwareGaussian, NeverMixesAcrossAnIdEdgeAndKeepsConstants) {
  const int w = 30, h = 20;
  std::vector<int32_t> id(size_t(w) * h);
  std::vector<Vec3> values(id.size());
  for (size_t p = 0; p < id.size(); ++p) {
    id[p] = (p % w) + (p / w) < 25 ? 7 : 9;
    values[p] = id[p] == 7 ? Vec3(1.0) : Vec3(1000.0);
  }
  id[0] = -1;
  const auto out = idAwareGaussian(w, h, values, id, 3, 1.5, Parallel(2));
  for (size_t p = 0; p < id.size(); ++p) {
    if (id[p] < 0) {
      EXPECT_EQ(out[p], Vec3(0.0));
      continue;
    }
    ASSERT_NEAR(out[p].x, values[p].x, 1e-9 * values[p].x) << p;
  }
}

TEST(IdAwareGaussian, SmoothsWithinASurface) {
  const int w = 9, h = 9;
  const std::vector<int32_t> id(size_t(w) * h, 0);
  std::vector<Vec3> values(id.size(), Vec3(0.0));
  values[4 * w + 4] = Vec3(1.0);  // an impulse spreads, its total kept in the interior
  const auto out = idAwareGaussian(w, h, values, id, 2, 1.0, Parallel(1));
  double total = 0;
  for (const Vec3& v : out) total += v.x;
  EXPECT_NEAR(total, 1.0, 1e-12);
  EXPECT_LT(out[4 * w + 4].x, 0.5);
  EXPECT_GT(out[4 * w + 5].x, 0.0);
}

}  // namespace
}  // namespace penumbra::gi
