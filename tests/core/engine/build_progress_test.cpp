// A build's progress reports name each step as it comes (ordering, cube, receivers, then casting
// and illumination at once), each step's done rises to its total, and illumination counts
// vertices lit, not receivers: one receiver (a floor) may hold most of the vertices, and a count
// of receivers held its fraction while that receiver was lit (seconds in the page, under a model
// whose floor's DM vertices were all lit).
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

struct Build {
  std::vector<Report> reports;
  BuildStats stats;
  size_t largestLit = 0;  // the vertices of the receiver with the most lit (not lattice-displayed)
};

Build reportsOfBuild(const Scene& scene, const EngineSettings& settings) {
  std::mutex mutex;
  Build build;
  const Engine engine(scene, settings, [&](const char* step, size_t done, size_t total) {
    std::lock_guard lock(mutex);
    build.reports.push_back({step, done, total});
  });
  build.stats = engine.stats();
  for (const Engine::Receiver& receiver : engine.receivers())
    if (!receiver.fromLattice) build.largestLit = std::max(build.largestLit, receiver.tree.vertices().size());
  return build;
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

// A model resting on the floor (its floor keeps its cells: contact lines) and a room of cubes, their
// floors holding most vertices lit, at 1 and 2 threads, with the cells not refined (as served).
TEST(BuildProgress, IlluminationCountsTheVerticesLitAndMovesWithinTheLargestReceiver) {
  struct Case {
    std::string name;
    Scene scene;
  };
  std::vector<Case> cases;
  cases.push_back({"knot 600 resting", makeModelScene({.kind = ModelKind::TorusKnot, .triangles = 600, .rest = true})});
  cases.push_back({"cubes 15", makeCubesScene({.cubes = 15})});
  for (const Case& c : cases) {
    for (int threads : {1, 2}) {
      const std::string name = c.name + ", " + std::to_string(threads) + " threads";
      EngineSettings settings;
      settings.threads = threads;
      settings.meshTolerance = 0;
      const Build build = reportsOfBuild(c.scene, settings);
      expectStepsInOrderRisingToTheirTotals(build.reports, name);
      const size_t lit = build.stats.vertices - build.stats.latticeVertices;
      std::set<size_t> counts;
      size_t finalTotal = 0;
      for (const Report& report : build.reports)
        if (report.step == "illumination") {
          counts.insert(report.done);
          finalTotal = report.total;
        }
      EXPECT_EQ(finalTotal, lit) << name << ": illumination's total is the vertices lit";
      // Within the largest receiver a report per kVerticesPerBeat vertices, a few merged where
      // threads report at once (small receivers' counts show with the casts between them).
      EXPECT_GT(build.largestLit, 1000u) << name << ": no receiver holds many vertices";
      EXPECT_GE(counts.size(), build.largestLit / Engine::kVerticesPerBeat / 2) << name;
    }
  }
}

}  // namespace
}  // namespace penumbra
