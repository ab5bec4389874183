// CellMemo packs a cell's pieces, points and triangles into one array: seeded random outputs
// (chunk keys of any sign and size, own values, several pieces) read back exactly. And
// PerLightValues keeps its rows through resizes.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>

#include "core/illum/per_light_values.h"
#include "core/mesh/cell_memo.h"

namespace penumbra {
namespace {

CellMemo::Output randomOutput(std::mt19937_64& rng) {
  CellMemo::Output out;
  std::uniform_int_distribution<int> small(0, 6);
  const int64_t extremes[] = {0, -1, 1, std::numeric_limits<int64_t>::min(), std::numeric_limits<int64_t>::max(),
                              int64_t(1) << 40, -(int64_t(1) << 33)};
  const int pieces = 1 + small(rng);
  for (int p = 0; p < pieces; ++p) {
    // Offsets wrap around (in unsigned arithmetic, defined) past the extremes.
    const MeshChunkKey chunk{int64_t(uint64_t(extremes[small(rng)]) + uint64_t(small(rng))),
                             int64_t(uint64_t(extremes[small(rng)]) - uint64_t(small(rng)))};
    const int points = 3 + small(rng);
    const uint32_t first = uint32_t(out.points.size());
    for (int k = 0; k < points; ++k) {
      if (rng() % 3 == 0) {
        out.points.push_back(CellMemo::kOwnValue | uint32_t(out.ownValues.size()));
        VertexIrradiance value;
        value.irradiance = Vec3(double(rng() % 1000) / 7.0, 1.5, -0.0);
        value.lightClass = LightClass(rng() % 3);
        out.ownValues.push_back({Vec2(double(rng() % 100) / 3.0, -2.25), value});
      } else {
        out.points.push_back(uint32_t(rng() & CellMemo::kIndexMask) | (rng() % 2 ? CellMemo::kDarkCorner : 0));
      }
    }
    for (int t = 0; t + 2 < points; ++t) out.triangles.push_back({first, first + uint32_t(t) + 1, first + uint32_t(t) + 2});
    out.pieces.push_back({chunk, uint32_t(out.points.size()), uint32_t(out.triangles.size())});
  }
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
      EXPECT_EQ(memo.piece(i).trianglesEnd, out.pieces[i].trianglesEnd);
    }
    ASSERT_EQ(memo.pointCount(), out.points.size());
    for (size_t e = 0; e < out.points.size(); ++e) EXPECT_EQ(memo.point(e), out.points[e]);
    for (size_t t = 0; t < out.triangles.size(); ++t) EXPECT_EQ(memo.triangle(t), out.triangles[t]);
    for (uint32_t k = 0; k < out.ownValues.size(); ++k) {
      EXPECT_EQ(memo.ownValue(k).first, out.ownValues[k].first);
      EXPECT_TRUE(identicalValue(memo.ownValue(k).second, out.ownValues[k].second));
    }
    if (HasFailure()) return;
  }
}

TEST(CellMemo, DefaultIsInvalidAndEmpty) {
  const CellMemo memo;
  EXPECT_FALSE(memo.valid());
  EXPECT_EQ(memo.pieceCount(), 0u);
  EXPECT_EQ(memo.pointCount(), 0u);
}

TEST(PerLightValues, RowsSurviveResizes) {
  PerLightValues values;
  values.assign(3, 2);
  ASSERT_EQ(values.size(), 3u);
  ASSERT_EQ(values[1].size(), 2u);
  EXPECT_FALSE(values[2][1].applies);  // a default entry is no light
  for (size_t v = 0; v < 3; ++v)
    for (size_t l = 0; l < 2; ++l) values[v][l].factor = double(10 * v + l);

  values.resize(5, 2);  // more rows, same lights: rows kept, new ones default
  ASSERT_EQ(values.size(), 5u);
  EXPECT_EQ(values[2][1].factor, 21.0);
  EXPECT_EQ(values[4][0].factor, 0.0);

  values.resize(4, 3);  // a light more: each row keeps its first entries
  ASSERT_EQ(values.lightCount(), 3u);
  ASSERT_EQ(values.size(), 4u);
  EXPECT_EQ(values[1][0].factor, 10.0);
  EXPECT_EQ(values[1][1].factor, 11.0);
  EXPECT_EQ(values[1][2].factor, 0.0);

  values.resize(2, 1);  // fewer of both
  ASSERT_EQ(values.size(), 2u);
  EXPECT_EQ(values[1][0].factor, 10.0);

  values.assign(7, 0);  // no lights: rows without entries
  EXPECT_EQ(values.size(), 7u);
  EXPECT_TRUE(values[3].empty());
}

}  // namespace
}  // namespace penumbra
