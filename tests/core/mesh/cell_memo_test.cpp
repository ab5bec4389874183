// CellMemo packs a cell's pieces, points, fans (or listed triangles) and own values into one array: seeded random outputs
// (chunk keys of any sign and size, own values, several pieces) read back exactly. And
// PerLightValues keeps its rows through resizes.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

#include "core/illum/per_light_values.h"
#include "core/mesh/cell_memo.h"
#include "core/mesh/cell_triangulation.h"

namespace penumbra {
namespace {

CellMemo::Output randomOutput(std::mt19937_64& rng) {
  CellMemo::Output out;
  std::uniform_int_distribution<int> small(0, 6);
  out.lights = size_t(small(rng));  // no light too: a copy is then only its position
  const int64_t extremes[] = {0, -1, 1, std::numeric_limits<int64_t>::min(), std::numeric_limits<int64_t>::max(),
                              int64_t(1) << 40, -(int64_t(1) << 33)};
  const int pieces = 1 + small(rng);
  for (int p = 0; p < pieces; ++p) {
    // Offsets wrap around (in unsigned arithmetic, defined) past the extremes.
    const MeshChunkKey chunk{int64_t(uint64_t(extremes[small(rng)]) + uint64_t(small(rng))),
                             int64_t(uint64_t(extremes[small(rng)]) - uint64_t(small(rng)))};
    const int points = 3 + small(rng);
    for (int k = 0; k < points; ++k) {
      if (rng() % 3 == 0) {
        out.points.push_back(CellMemo::kOwnValue | uint32_t(out.ownAt.size()));
        out.ownAt.push_back(Vec2(double(rng() % 100) / 3.0, -2.25));
        for (size_t l = 0; l < out.lights; ++l) {
          VertexLight light;
          light.setFactor(l % 2 ? -0.0 : double(rng() % 1000) / 7.0);
          light.setComparisons(rng() % VertexLight::kMaxComparisons);
          light.setLightClass(LightClass(rng() % 3));
          light.setApplies(rng() % 2);
          light.setDecidedBy(VertexCase(rng() % 4));
          out.ownLights.push_back(light);
        }
      } else {
        out.points.push_back(uint32_t(rng() & CellMemo::kIndexMask) | (rng() % 2 ? CellMemo::kDarkCorner : 0));
      }
    }
    CellFan fan{rng() % 2 ? CellFan::kCentre : uint32_t(rng() % uint32_t(points))};
    if (rng() % 3 == 0) {  // a refined piece: its triangles listed
      for (uint64_t t = rng() % 5; t > 0; --t)
        out.triangles.push_back(CellMemo::packTriangle(
            {uint32_t(rng() % CellMemo::kMaxPiecePoints), uint32_t(rng() % CellMemo::kMaxPiecePoints),
             uint32_t(rng() % CellMemo::kMaxPiecePoints)}));
      fan = CellFan::listedUpTo(uint32_t(out.triangles.size()));
    }
    out.pieces.push_back({chunk, uint32_t(out.points.size()), fan});
  }
  out.capped = rng() % 2;
  return out;
}

TEST(CellMemo, PackedOutputReadsBackExactly) {
  std::mt19937_64 rng(20261127);
  for (int trial = 0; trial < 500; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const CellMemo::Output out = randomOutput(rng);
    const uint64_t inputs = rng();
    const CellMemo memo(inputs, out);
    ASSERT_TRUE(memo.valid());
    EXPECT_EQ(memo.inputs(), inputs);
    ASSERT_EQ(memo.pieceCount(), out.pieces.size());
    for (size_t i = 0; i < out.pieces.size(); ++i) {
      EXPECT_EQ(memo.piece(i).chunk, out.pieces[i].chunk);
      EXPECT_EQ(memo.piece(i).pointsEnd, out.pieces[i].pointsEnd);
      EXPECT_EQ(memo.piece(i).fan.apex, out.pieces[i].fan.apex);
    }
    ASSERT_EQ(memo.pointCount(), out.points.size());
    for (size_t e = 0; e < out.points.size(); ++e) EXPECT_EQ(memo.point(e), out.points[e]);
    ASSERT_EQ(memo.lightCount(), out.lights);
    std::vector<VertexLight> row;
    for (uint32_t k = 0; k < out.ownAt.size(); ++k) {
      EXPECT_EQ(memo.ownAt(k), out.ownAt[k]);
      memo.ownLights(k, row);
      ASSERT_EQ(row.size(), out.lights);
      for (size_t l = 0; l < out.lights; ++l)  // every bit: factor (−0 too), counts, flags
        EXPECT_EQ(std::memcmp(&row[l], &out.ownLights[k * out.lights + l], sizeof(VertexLight)), 0);
    }
    EXPECT_EQ(memo.capped(), out.capped);
    for (size_t k = 0; k < out.triangles.size(); ++k)
      EXPECT_EQ(memo.listedTriangle(k), CellMemo::unpackTriangle(out.triangles[k]));
    const CellMemo copy = memo;  // a copy holds the same words
    for (size_t k = 0; k < out.triangles.size(); ++k) EXPECT_EQ(copy.listedTriangle(k), memo.listedTriangle(k));
    EXPECT_EQ(copy.capped(), memo.capped());
    ASSERT_EQ(copy.pointCount(), memo.pointCount());
    for (size_t e = 0; e < out.points.size(); ++e) EXPECT_EQ(copy.point(e), memo.point(e));
    for (uint32_t k = 0; k < out.ownAt.size(); ++k) EXPECT_EQ(copy.ownAt(k), memo.ownAt(k));
    if (HasFailure()) return;
  }
}

TEST(CellMemo, DefaultIsInvalidAndEmpty) {
  const CellMemo memo;
  EXPECT_FALSE(memo.valid());
  EXPECT_EQ(memo.pieceCount(), 0u);
  EXPECT_EQ(memo.pointCount(), 0u);
}

// A fan's triangles cover the loop once, counter-clockwise, with no repeated vertex.
TEST(CellFan, TrianglesCoverTheLoop) {
  const Polygon2 square = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const CellFan corner = fanOfConvexCell(square, 1e-9);
  ASSERT_FALSE(corner.usesCentre());
  ASSERT_EQ(corner.triangleCount(4), 2u);
  // A side's midpoint makes its ends unusable as apexes; with every side split, only the centre.
  const Polygon2 split = {{0, 0}, {0.5, 0}, {1, 0}, {1, 0.5}, {1, 1}, {0.5, 1}, {0, 1}, {0, 0.5}};
  const CellFan centre = fanOfConvexCell(split, 1e-9);
  ASSERT_TRUE(centre.usesCentre());
  ASSERT_EQ(centre.triangleCount(8), 8u);
  for (const auto& [polygon, fan] : {std::pair{square, corner}, std::pair{split, centre}}) {
    const Polygon2& loop = polygon;  // a lambda below reads it (clang does not capture bindings)
    const uint32_t n = uint32_t(loop.size());
    double area = 0;
    for (uint32_t t = 0; t < fan.triangleCount(n); ++t) {
      const auto tri = fan.triangle(n, t);
      const auto at = [&](uint32_t i) { return i == n ? areaCentroid(loop) : loop[i]; };
      const Vec2 a = at(tri[0]), b = at(tri[1]), c = at(tri[2]);
      const double twice = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
      EXPECT_GT(twice, 0) << "triangle " << t << " is not counter-clockwise";
      area += twice / 2;
    }
    EXPECT_NEAR(area, 1.0, 1e-12);
  }
  EXPECT_EQ(CellFan{}.triangleCount(2), 0u);  // no triangles below three vertices
}

TEST(PerLightValues, RowsSurviveResizes) {
  PerLightValues values;
  values.assign(3, 2);
  ASSERT_EQ(values.size(), 3u);
  ASSERT_EQ(values[1].size(), 2u);
  EXPECT_FALSE(values[2][1].applies());  // a default entry is no light
  for (size_t v = 0; v < 3; ++v)
    for (size_t l = 0; l < 2; ++l) values[v][l].setFactor(double(10 * v + l));

  values.resize(5, 2);  // more rows, same lights: rows kept, new ones default
  ASSERT_EQ(values.size(), 5u);
  EXPECT_EQ(values[2][1].factor(), 21.0);
  EXPECT_EQ(values[4][0].factor(), 0.0);

  values.resize(4, 3);  // a light more: each row keeps its first entries
  ASSERT_EQ(values.lightCount(), 3u);
  ASSERT_EQ(values.size(), 4u);
  EXPECT_EQ(values[1][0].factor(), 10.0);
  EXPECT_EQ(values[1][1].factor(), 11.0);
  EXPECT_EQ(values[1][2].factor(), 0.0);

  values.resize(2, 1);  // fewer of both
  ASSERT_EQ(values.size(), 2u);
  EXPECT_EQ(values[1][0].factor(), 10.0);

  values.assign(7, 0);  // no lights: rows without entries
  EXPECT_EQ(values.size(), 7u);
  EXPECT_TRUE(values[3].empty());
}

}  // namespace
}  // namespace penumbra
