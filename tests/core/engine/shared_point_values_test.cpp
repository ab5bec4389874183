// Values shared between neighbouring cells (core/mesh/shared_point_values.h): the table hands
// back exactly what was kept, only for the list it was kept with, the first keep wins, and it
// holds under threads; and on seeded model and box scenes every cell a CellLighter emits with a
// shared table (cells lit in a shuffled order, so either neighbour may come first) is bit for bit
// the cell it emits alone — the sharing saves work and changes nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "core/engine/engine.h"
#include "core/mesh/cell_lighting.h"
#include "core/mesh/shared_point_values.h"
#include "scenegen/cubes_scene.h"
#include "scenegen/model_scene.h"

namespace penumbra {
namespace {

VertexLight lightOf(double factor, uint32_t comparisons) {
  VertexLight light;
  light.setFactor(factor);
  light.setComparisons(comparisons);
  light.setLightClass(LightClass::Penumbra);
  return light;
}

// Every field alike, the factor bit for bit (VertexLight's spare bits are not compared).
bool sameLights(std::span<const VertexLight> a, std::span<const VertexLight> b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const double fa = a[i].factor(), fb = b[i].factor();
    if (std::memcmp(&fa, &fb, sizeof fa) != 0 || a[i].comparisons() != b[i].comparisons() ||
        a[i].lightClass() != b[i].lightClass() || a[i].applies() != b[i].applies() ||
        a[i].decidedBy() != b[i].decidedBy())
      return false;
  }
  return true;
}

TEST(SharedPointValues, HandsBackWhatWasKeptForItsListOnlyAndTheFirstKeepWins) {
  const OccluderList one, other;
  SharedPointValues table(2);
  std::vector<VertexLight> out;
  EXPECT_FALSE(table.find(Vec2(0.5, 0.25), &one, out));
  const std::vector<VertexLight> kept = {lightOf(0.125, 7), lightOf(0.75, 9)};
  table.keep(Vec2(0.5, 0.25), &one, kept);
  out.push_back(lightOf(3, 1));  // find appends
  ASSERT_TRUE(table.find(Vec2(0.5, 0.25), &one, out));
  ASSERT_EQ(out.size(), 3u);
  EXPECT_TRUE(sameLights(std::span(out).subspan(1), kept));
  out.clear();
  EXPECT_FALSE(table.find(Vec2(0.5, 0.25), &other, out)) << "another list's values are its own";
  EXPECT_FALSE(table.find(Vec2(0.5, std::nextafter(0.25, 1.0)), &one, out)) << "exact positions only";
  table.keep(Vec2(0.5, 0.25), &other, std::vector<VertexLight>{lightOf(1, 1), lightOf(2, 2)});
  ASSERT_TRUE(table.find(Vec2(0.5, 0.25), &one, out));
  EXPECT_TRUE(sameLights(out, kept)) << "a second keep replaced the first";
  EXPECT_TRUE(out.size() == 2);
}

TEST(SharedPointValues, ThreadsKeepingAndFindingSeeOnlyWhatWasKeptAtEachPoint) {
  const OccluderList list;
  SharedPointValues table(1);
  // Each point's value is a function of the point: whoever keeps it first, every find agrees.
  auto valueAt = [](int i) { return lightOf(double(i) / 7.0, uint32_t(i)); };
  std::vector<std::thread> threads;
  std::vector<int> wrong(4, 0), found(4, 0);
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      std::mt19937 rng(uint32_t(t) + 11);
      std::vector<VertexLight> out;
      for (int k = 0; k < 20000; ++k) {
        const int i = int(rng() % 3000);
        const Vec2 q(double(i) * 0.001, -double(i));
        out.clear();
        if (table.find(q, &list, out)) {
          ++found[t];
          if (!sameLights(out, std::vector<VertexLight>{valueAt(i)})) ++wrong[t];
        } else {
          table.keep(q, &list, std::vector<VertexLight>{valueAt(i)});
        }
      }
    });
  for (std::thread& thread : threads) thread.join();
  for (int t = 0; t < 4; ++t) {
    EXPECT_EQ(wrong[t], 0) << "thread " << t;
    EXPECT_GT(found[t], 0) << "thread " << t;
  }
}

// The two emitted cells word for word: points, own positions and values, pieces, triangles.
void expectSameCell(const CellMemo& got, const CellMemo& expected, uint32_t cell) {
  SCOPED_TRACE("cell " + std::to_string(cell));
  ASSERT_EQ(got.pointCount(), expected.pointCount());
  for (size_t e = 0; e < got.pointCount(); ++e) ASSERT_EQ(got.point(e), expected.point(e));
  ASSERT_EQ(got.pieceCount(), expected.pieceCount());
  std::vector<VertexLight> a, b;
  for (size_t e = 0; e < got.pointCount(); ++e) {
    const uint32_t word = got.point(e);
    if (!(word & CellMemo::kOwnValue)) continue;
    const uint32_t own = word & CellMemo::kIndexMask;
    ASSERT_EQ(got.ownAt(own), expected.ownAt(own));
    got.ownLights(own, a);
    expected.ownLights(own, b);
    ASSERT_TRUE(sameLights(a, b)) << "own point " << own;
  }
  uint32_t listed = 0;  // the cell's listed triangles end at its last refined piece's end
  for (size_t i = 0; i < got.pieceCount(); ++i) {
    ASSERT_EQ(got.piece(i).pointsEnd, expected.piece(i).pointsEnd);
    ASSERT_EQ(got.piece(i).fan.listed(), expected.piece(i).fan.listed());
    if (got.piece(i).fan.listed()) listed = std::max(listed, got.piece(i).fan.listedEnd());
  }
  for (uint32_t k = 0; k < listed; ++k)
    ASSERT_EQ(got.listedTriangle(k), expected.listedTriangle(k));
}

// Every live cell of every receiver, lit alone and lit with a table shared across the
// receiver's cells in a shuffled order: the same CellMemo, word for word. Returns the cells.
size_t expectSharingChangesNothing(const Engine& engine, uint64_t seed) {
  const MeshGrid grid = engine.meshGrid();
  const double chunkSide = grid.spacing * grid.chunkSquares;
  std::mt19937_64 rng(seed);
  size_t cells = 0;
  for (const Engine::Receiver& r : engine.receivers()) {
    const MeshSource source{r.face, r.frame, r.tree, r.perLight};
    std::vector<CellId> live;
    for (size_t c = 0; c < r.tree.mesh().cellSlots(); ++c)
      if (r.tree.mesh().cell(CellId(uint32_t(c))).alive) live.push_back(CellId(uint32_t(c)));
    std::shuffle(live.begin(), live.end(), rng);
    SharedPointValues shared(r.perLight.lightCount());
    CellLighter alone(engine.scene(), source, grid.spacing, chunkSide, grid.refine);
    CellLighter sharing(engine.scene(), source, grid.spacing, chunkSide, grid.refine, &shared);
    for (CellId c : live) {
      CellMemo expected, got;
      const uint64_t inputs = alone.gather(c);
      alone.emit(c, expected);
      EXPECT_EQ(sharing.gather(c), inputs);
      sharing.emit(c, got);
      ++cells;
      expectSameCell(got, expected, c.index);
      if (::testing::Test::HasFatalFailure()) return cells;
    }
  }
  return cells;
}

TEST(SharedPointValues, CellsLitWithSharedValuesEqualCellsLitAloneOnModelsAndBoxes) {
  size_t cells = 0;
  for (const ModelKind kind : {ModelKind::Teapot, ModelKind::Bowl})
    for (const bool rest : {false, true}) {
      SCOPED_TRACE(std::string(modelKindName(kind)) + (rest ? " resting" : " floating"));
      const Engine engine(makeModelScene({.kind = kind, .triangles = 200, .rest = rest, .smooth = rest}));
      cells += expectSharingChangesNothing(engine, 7);
    }
  CubesSceneOptions boxes;
  boxes.cubes = 15;
  boxes.twoLights = true;  // two values a point
  boxes.seed = 3;
  const Engine engine(makeCubesScene(boxes));
  cells += expectSharingChangesNothing(engine, 8);
  EXPECT_GT(cells, 5000u);
}

}  // namespace
}  // namespace penumbra
