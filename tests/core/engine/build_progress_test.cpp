// A build's progress reports name each step as it comes (ordering, cube, receivers, then casting
// and illumination at once), each step's done rises to its total, and illumination counts
// vertices lit, not receivers: one receiver (a floor) may hold most of the vertices, and a count
// of receivers held its fraction while that receiver was lit (seconds in the page, under a model
// whose floor's DM vertices were all lit). The display mesh's triangulation counts cells likewise.
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

struct ProgressCase {
  std::string name;
  Scene scene;
};

// A knot of 600 triangles resting on the floor and the room of 15 cubes: their floors hold most
// of the vertices and cells.
std::vector<ProgressCase> restingKnotAndCubes() {
  std::vector<ProgressCase> cases;
  cases.push_back({"knot 600 resting", makeModelScene({.kind = ModelKind::TorusKnot, .triangles = 600, .rest = true})});
  cases.push_back({"cubes 15", makeCubesScene({.cubes = 15})});
  return cases;
}

// A model resting on the floor (its floor keeps its cells: contact lines) and a room of cubes, their
// floors holding most vertices lit, at 1 and 2 threads, with the cells not refined (as served).
TEST(BuildProgress, IlluminationCountsTheVerticesLitAndMovesWithinTheLargestReceiver) {
  for (const ProgressCase& c : restingKnotAndCubes()) {
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

// The display mesh counts cells (lattice squares where a floor is meshed from its lattice), all
// known before any is lit: the floor, holding most of them, moves the fraction as it is meshed,
// where a count of receivers held it (the page's bar stood still for most of a dense room's
// meshing). A floating knot's floor is meshed from its lattice, the resting knot's and the cubes'
// from their cells; a second mesh() after no edit counts every cell again, at once.
TEST(BuildProgress, TriangulationCountsCellsAndMovesWithinTheLargestReceiver) {
  std::vector<ProgressCase> cases = restingKnotAndCubes();
  cases.insert(cases.begin(), {"knot 600 floating", makeModelScene({.kind = ModelKind::TorusKnot, .triangles = 600})});
  for (const ProgressCase& c : cases) {
    for (int threads : {1, 2}) {
      const std::string name = c.name + ", " + std::to_string(threads) + " threads";
      EngineSettings settings;
      settings.threads = threads;
      Engine engine(c.scene, settings);
      size_t cellSlots = 0, largest = 0;
      bool anyLattice = false;
      for (const Engine::Receiver& receiver : engine.receivers()) {
        anyLattice = anyLattice || receiver.fromLattice;
        if (receiver.fromLattice) continue;
        cellSlots += receiver.tree.mesh().cellSlots();
        largest = std::max(largest, receiver.tree.mesh().cellSlots());
      }
      EXPECT_EQ(anyLattice, c.name == "knot 600 floating") << name;
      for (int call = 0; call < 2; ++call) {
        std::vector<Report> reports;
        std::mutex mutex;
        engine.mesh([&](const char* step, size_t done, size_t total) {
          std::lock_guard lock(mutex);
          reports.push_back({step, done, total});
        });
        ASSERT_FALSE(reports.empty()) << name;
        std::set<size_t> counts;
        for (const Report& report : reports) {
          EXPECT_EQ(report.step, "triangulation") << name;
          EXPECT_EQ(report.total, reports.front().total) << name << ": the total is known at the start";
          EXPECT_LE(report.done, report.total) << name;
          if (counts.size()) EXPECT_GE(report.done, *counts.rbegin()) << name << ": went back";
          counts.insert(report.done);
        }
        EXPECT_EQ(reports.back().done, reports.back().total) << name;
        // Cell receivers count their tree's cell slots; a lattice floor adds its squares.
        if (anyLattice)
          EXPECT_GT(reports.back().total, cellSlots) << name;
        else
          EXPECT_EQ(reports.back().total, cellSlots) << name;
        if (call == 0) {
          // The largest receiver alone reports about every kCellsPerReport of its cells (the
          // floating knot's floor: its squares, the units past the cell receivers').
          const size_t floor = anyLattice ? reports.back().total - cellSlots : largest;
          EXPECT_GT(floor, 400u) << name;
          EXPECT_GE(counts.size(), floor / ReceiverMeshMemo::kCellsPerReport / 2) << name;
        }
      }
    }
  }
}

}  // namespace
}  // namespace penumbra
