// A build's progress reports name each step as it comes (ordering, cube, receivers, then casting
// and illumination at once), each step's done rises to its total, and illumination counts
// vertices lit, not receivers: under a model the floor, one receiver, holds most of the
// vertices, and a count of receivers held its fraction while that receiver was lit (seconds in
// the page, where the served mesh keeps every DM vertex).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "core/engine/engine.h"
#include "scenegen/cubes_scene.h"
#include "scenegen/model_scene.h"

namespace penumbra {
namespace {

struct Report {
  std::string step;
  size_t done, total;
};

std::vector<Report> reportsOfBuild(const Scene& scene, const EngineSettings& settings, BuildStats& stats) {
  std::mutex mutex;
  std::vector<Report> reports;
  const Engine engine(scene, settings, [&](const char* step, size_t done, size_t total) {
    std::lock_guard lock(mutex);
    reports.push_back({step, done, total});
  });
  stats = engine.stats();
  return reports;
}

void expectStepsInOrderRisingToTheirTotals(const std::vector<Report>& reports, const std::string& scene) {
  std::vector<std::string> firstSeen;
  std::map<std::string, Report> last;
  for (const Report& report : reports) {
    if (!last.count(report.step)) firstSeen.push_back(report.step);
    else EXPECT_GE(report.done, last.at(report.step).done) << scene << ": " << report.step << " went back";
    EXPECT_LE(report.done, report.total) << scene << ": " << report.step;
    last[report.step] = report;
  }
  const std::vector<std::string> expected = {"ordering", "cube", "receivers", "casting", "illumination"};
  ASSERT_EQ(firstSeen, expected) << scene;
  for (const auto& [step, report] : last) EXPECT_EQ(report.done, report.total) << scene << ": " << step << " ended short";
}

// Scenes whose floor holds most vertices: a model (no lattice display: tolerance 0, as served) and
// a room of cubes, at 1 and 2 threads.
TEST(BuildProgress, IlluminationCountsTheVerticesLitAndMovesWithinTheLargestReceiver) {
  struct Case {
    std::string name;
    Scene scene;
  };
  std::vector<Case> cases;
  cases.push_back({"knot 600", makeModelScene({.kind = ModelKind::TorusKnot, .triangles = 600})});
  cases.push_back({"cubes 15", makeCubesScene({.cubes = 15})});
  for (const Case& c : cases) {
    for (int threads : {1, 2}) {
      const std::string name = c.name + ", " + std::to_string(threads) + " threads";
      EngineSettings settings;
      settings.threads = threads;
      settings.meshTolerance = 0;
      BuildStats stats;
      const std::vector<Report> reports = reportsOfBuild(c.scene, settings, stats);
      expectStepsInOrderRisingToTheirTotals(reports, name);
      const size_t lit = stats.vertices - stats.latticeVertices;
      std::set<size_t> counts;
      size_t finalTotal = 0;
      for (const Report& report : reports)
        if (report.step == "illumination") {
          counts.insert(report.done);
          finalTotal = report.total;
        }
      EXPECT_EQ(finalTotal, lit) << name << ": illumination's total is the vertices lit";
      // A report per kVerticesPerBeat vertices, a few merged where threads report at once.
      EXPECT_GE(counts.size(), lit / Engine::kVerticesPerBeat / 2) << name;
    }
  }
}

}  // namespace
}  // namespace penumbra
