// A convex face rebuilt from the triangles that tile it (interchange/face_outline.h): the
// corners only, in the triangles' winding, the points on its edges left out even when float32
// storage moved them off the edge.
#include "interchange/face_outline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace penumbra::interchange {
namespace {

// The unit square at height 2 tiled around its centre (index 4) and an edge midpoint (5), the
// midpoint rounded off the edge by an ulp as a float would put it.
std::vector<Vec3> squarePoints() {
  return {{0, 2, 0}, {0, 2, 1},     {1, 2, 1},
          {1, 2, 0}, {0.5, 2, 0.5}, {0.5, 2, std::nextafter(1.0, 2.0)}};
}
const std::vector<IndexPolygon> kSquareTiles = {
    {0, 1, 4}, {1, 5, 4}, {5, 2, 4}, {2, 3, 4}, {3, 0, 4}};

TEST(FaceOutline, TheCornersInTheTrianglesWinding) {
  const IndexPolygon outline = convexOutline(squarePoints(), kSquareTiles, 1e-9);
  ASSERT_EQ(outline.size(), 4u);
  // Counter-clockwise about +y, as the tiles are: 0 → 1 → 2 → 3 from some first corner.
  const auto first = std::find(outline.begin(), outline.end(), 0) - outline.begin();
  for (size_t k = 0; k < 4; ++k) EXPECT_EQ(outline[(size_t(first) + k) % 4], int(k));
  // Without the tolerance the midpoint just outside the edge is a corner.
  EXPECT_EQ(convexOutline(squarePoints(), kSquareTiles, 0).size(), 5u);
}

TEST(FaceOutline, FacesByNumberInOrderAndMixedTrianglesRefused) {
  std::vector<Vec3> points = squarePoints();
  for (const Vec3& p : squarePoints())
    points.push_back(p + Vec3(0, 1, 0));  // a second square above
  std::vector<IndexPolygon> triangles;
  for (const IndexPolygon& t : kSquareTiles) triangles.push_back({t[0] + 6, t[1] + 6, t[2] + 6});
  for (const IndexPolygon& t : kSquareTiles) triangles.push_back(t);
  std::vector<double> faceOf(12, 0);
  for (size_t i = 0; i < 6; ++i) faceOf[i] = 1;  // the lower square is face 1, listed second
  const auto faces = facesFromTriangles(points, triangles, faceOf);
  ASSERT_TRUE(faces);
  ASSERT_EQ(faces->size(), 2u);
  for (int i : (*faces)[0]) EXPECT_GE(i, 6);  // face 0 first: the upper square
  for (int i : (*faces)[1]) EXPECT_LT(i, 6);
  faceOf[4] = 0;  // a triangle whose corners name two faces: not Penumbra's export
  EXPECT_FALSE(facesFromTriangles(points, triangles, faceOf));
}

}  // namespace
}  // namespace penumbra::interchange
