// Polygon repair: pieces are convex, planar, wound like the input, and cover it.
#include <gtest/gtest.h>

#include "core/geom/polygon.h"
#include "core/geom/tolerance.h"
#include "interchange/polygon_repair.h"

namespace penumbra::interchange {
namespace {

Polygon3 pointsOf(const std::vector<Vec3>& positions, const IndexPolygon& polygon) {
  Polygon3 out;
  for (int i : polygon) out.push_back(positions[size_t(i)]);
  return out;
}

IndexPolygon firstN(int n) {
  IndexPolygon p;
  for (int i = 0; i < n; ++i) p.push_back(i);
  return p;
}

void expectConvexPiecesCovering(const std::vector<Vec3>& positions, const PolygonRepair& repair,
                                double expectedArea, const Vec3& normal) {
  double total = 0;
  for (const IndexPolygon& piece : repair.pieces) {
    const Polygon3 points = pointsOf(positions, piece);
    EXPECT_TRUE(isConvex(points));
    EXPECT_LE(planarityError(points), kRelativePlanarity);
    EXPECT_GT(glm::dot(newellVector(points), normal), 0) << "piece wound against the input";
    total += area(points);
  }
  EXPECT_NEAR(total, expectedArea, 1e-12 * expectedArea);
}

TEST(PolygonRepair, ConvexPlanarPolygonIsKeptAsIs) {
  const std::vector<Vec3> square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const PolygonRepair repair = repairPolygon(square, firstN(4));
  ASSERT_EQ(repair.pieces.size(), 1u);
  EXPECT_EQ(repair.pieces[0], firstN(4));
  EXPECT_FALSE(repair.nonPlanar || repair.nonConvex || repair.degenerate);
}

TEST(PolygonRepair, NonConvexLShapeBecomesConvexPieces) {
  // An L of area 3, counter-clockwise seen from +z.
  const std::vector<Vec3> l = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  const PolygonRepair repair = repairPolygon(l, firstN(6));
  EXPECT_TRUE(repair.nonConvex);
  EXPECT_FALSE(repair.nonPlanar);
  EXPECT_GE(repair.pieces.size(), 2u);  // joined back from 4 triangles
  EXPECT_LE(repair.pieces.size(), 3u);
  expectConvexPiecesCovering(l, repair, 3.0, {0, 0, 1});
}

TEST(PolygonRepair, NonConvexQuadBecomesTwoTriangles) {
  // A dart: the corner (1, 0.5) is reflex.
  const std::vector<Vec3> dart = {{0, 0, 0}, {2, 0, 0}, {1, 0.5, 0}, {1, 2, 0}};
  const PolygonRepair repair = repairPolygon(dart, firstN(4));
  EXPECT_TRUE(repair.nonConvex);
  EXPECT_EQ(repair.pieces.size(), 2u);
  expectConvexPiecesCovering(dart, repair, area(Polygon3(dart.begin(), dart.end())), {0, 0, 1});
}

TEST(PolygonRepair, NonPlanarQuadBecomesTwoPlanarTriangles) {
  const std::vector<Vec3> warped = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.2}, {0, 1, 0}};
  const PolygonRepair repair = repairPolygon(warped, firstN(4));
  EXPECT_TRUE(repair.nonPlanar);
  ASSERT_EQ(repair.pieces.size(), 2u);
  for (const IndexPolygon& piece : repair.pieces) EXPECT_EQ(piece.size(), 3u);
}

TEST(PolygonRepair, RepeatedVerticesAreDroppedAndSlivers) {
  const std::vector<Vec3> points = {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}};
  const PolygonRepair repair = repairPolygon(points, {0, 1, 2, 3, 4});
  EXPECT_EQ(repair.repeatedVerticesRemoved, 2u);  // 2 repeats 1 by position; 4 repeats 0 around the end
  ASSERT_EQ(repair.pieces.size(), 1u);
  EXPECT_EQ(repair.pieces[0], (IndexPolygon{0, 1, 3}));

  const std::vector<Vec3> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  EXPECT_TRUE(repairPolygon(line, firstN(3)).degenerate);
  EXPECT_TRUE(repairPolygon(line, {0, 1, 1}).degenerate);
}

TEST(PolygonRepair, JoinsCoplanarTrianglesIntoConvexPolygonsOnly) {
  // A unit square in two triangles and a triangle folded up along x = 1.
  const std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0.5, 1}};
  std::vector<IndexPolygon> pieces = {{0, 1, 2}, {0, 2, 3}, {1, 4, 2}};
  EXPECT_EQ(joinCoplanarConvex(p, pieces), 1u);
  ASSERT_EQ(pieces.size(), 2u);
  EXPECT_EQ(pieces[0].size(), 4u);
  EXPECT_TRUE(isConvex(pointsOf(p, pieces[0])));
}

}  // namespace
}  // namespace penumbra::interchange
