// referenceGridMesh: vertex and triangle counts, exact cover of each face,
// CCW triangles, watertight within a face, values equal to ExactReference.
#include "core/reference/grid_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "core/reference/exact_irradiance.h"

namespace penumbra {
namespace {

// A floor, a box standing on it (its bottom faces away from the light), a
// pentagon and a triangle on tilted planes, one light above.
Scene gridScene() {
  Light light{"lamp", {{-0.5, 3, -0.5}, {0.5, 3, -0.5}, {0.5, 3, 0.5}, {-0.5, 3, 0.5}}, Vec3{10}};
  Object floor;
  floor.id = "floor";
  floor.vertices = {{-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, {3, 0, -3}};
  floor.faces = {{0, 1, 2, 3}};
  Object box;
  box.id = "box";
  box.vertices = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                  {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  box.faces = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
  box.transform.translate = Vec3{0.3, 0.5, -0.2};
  box.transform.rotateDeg = Vec3{0, 30, 0};
  box.transform.scale = Vec3{0.5};
  Object shapes;
  shapes.id = "shapes";
  for (int i = 0; i < 5; ++i) {
    const double a = 2 * M_PI * i / 5;
    shapes.vertices.push_back(Vec3{1.8 + 0.5 * std::cos(a), 1.0 + 0.2 * std::cos(a), 0.5 * std::sin(a)});
  }
  shapes.vertices.push_back({-2.0, 0.8, 1.0});
  shapes.vertices.push_back({-1.2, 1.0, 1.2});
  shapes.vertices.push_back({-1.6, 1.3, 0.4});
  shapes.faces = {{4, 3, 2, 1, 0}, {5, 6, 7}};  // pentagon faces up-ish
  return Scene({light}, {}, {floor, box, shapes});
}

size_t expectedVertices(size_t corners, size_t n) {
  // (k-2) fan triangles of (n+1)(n+2)/2 points, sharing k-3 diagonals of n+1.
  return (corners - 2) * (n + 1) * (n + 2) / 2 - (corners - 3) * (n + 1);
}

TEST(GridMesh, CoversEveryReceivingFaceWithCcwTriangles) {
  const Scene scene = gridScene();
  const int n = 5;
  size_t lastDone = 0, calls = 0, reportedTotal = 0;
  const Mesh mesh = referenceGridMesh(scene, n, [&](size_t done, size_t total) {
    EXPECT_GE(done, lastDone);
    EXPECT_LE(done, total);
    lastDone = done;
    reportedTotal = total;
    ++calls;
  });

  size_t receiving = 0;
  for (const Face& f : scene.faces()) receiving += scene.receivesLight(f);
  ASSERT_EQ(mesh.receivers.size(), receiving);
  ASSERT_LT(receiving, scene.faces().size());  // the box bottom does not receive
  EXPECT_EQ(lastDone, mesh.vertexCount());
  EXPECT_EQ(reportedTotal, mesh.vertexCount());
  EXPECT_GE(calls, mesh.receivers.size());

  bool sawPentagon = false;
  for (const ReceiverMesh& r : mesh.receivers) {
    const Face* face = nullptr;
    for (const Face& f : scene.faces())
      if (f.id == r.face) face = &f;
    ASSERT_NE(face, nullptr);
    EXPECT_TRUE(scene.receivesLight(*face));
    const size_t k = face->polygon.size();
    sawPentagon |= k == 5;
    EXPECT_EQ(r.normal, face->plane.normal);
    EXPECT_EQ(r.positions.size(), expectedVertices(k, n));
    EXPECT_EQ(r.triangles.size(), (k - 2) * n * n);
    EXPECT_EQ(r.irradiance.size(), r.positions.size());
    EXPECT_EQ(r.classes.size(), r.positions.size());
    // The face's corners are vertices; every vertex lies on the face.
    for (const Vec3& corner : face->polygon)
      EXPECT_NE(std::find(r.positions.begin(), r.positions.end(), corner), r.positions.end());
    for (const Vec3& p : r.positions)
      EXPECT_NEAR(face->plane.signedDistance(p), 0, 1e-12 * scene.tolerance().sceneSize);

    // Areas add up to the face; each triangle is CCW about the face normal.
    double sum = 0;
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (const auto& t : r.triangles) {
      const Vec3 a = r.positions[t[0]], b = r.positions[t[1]], c = r.positions[t[2]];
      const double twice = glm::dot(glm::cross(b - a, c - a), face->plane.normal);
      EXPECT_GT(twice, 0);
      sum += 0.5 * twice;
      for (int e = 0; e < 3; ++e) ++edges[{t[e], t[(e + 1) % 3]}];
    }
    EXPECT_NEAR(sum, face->area, 1e-12 * face->area);
    // Watertight: each directed edge once; an interior edge also appears
    // reversed, and exactly k·n edges (the subdivided boundary) do not.
    size_t boundary = 0;
    for (const auto& [edge, count] : edges) {
      EXPECT_EQ(count, 1);
      boundary += !edges.count({edge.second, edge.first});
    }
    EXPECT_EQ(boundary, k * n);
  }
  EXPECT_TRUE(sawPentagon);
}

TEST(GridMesh, VertexValuesAreTheExactReference) {
  const Scene scene = gridScene();
  const Mesh mesh = referenceGridMesh(scene, 6);
  const ExactReference reference(scene);
  int classes[3] = {0, 0, 0};
  for (const ReceiverMesh& r : mesh.receivers) {
    for (size_t i = 0; i < r.positions.size(); ++i) {
      const PointIrradiance e = reference.evaluate(r.positions[i], r.normal);
      EXPECT_EQ(r.irradiance[i], e.irradiance);
      EXPECT_EQ(r.classes[i], e.lightClass);
      ++classes[int(e.lightClass)];
    }
  }
  // The scene does produce all three classes (the box shadows the floor).
  EXPECT_GT(classes[int(LightClass::Lit)], 0);
  EXPECT_GT(classes[int(LightClass::Penumbra)], 0);
  EXPECT_GT(classes[int(LightClass::Umbra)], 0);
}

TEST(GridMesh, GridSizeOneIsTheFan) {
  const Scene scene = gridScene();
  const Mesh mesh = referenceGridMesh(scene, 1);
  for (const ReceiverMesh& r : mesh.receivers) {
    EXPECT_EQ(r.triangles.size() + 2, r.positions.size());
  }
}

}  // namespace
}  // namespace penumbra
