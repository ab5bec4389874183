// Orientation repair of one object's faces: seeded closed meshes (star-shaped subdivided cubes)
// and open grids with random faces flipped come back wound one way, closed ones outward, with
// exactly the flipped faces turned back; components, closed ones and non-manifold edges counted.
// The checks (directed edges, signed volume) are the test's own, not the importer's.
#include "interchange/mesh_orientation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <tuple>

namespace penumbra::interchange {
namespace {

struct Mesh {
  std::vector<Vec3> positions;
  std::vector<IndexPolygon> faces;
};

// A cube [-1, 1]³ with n × n quads per side, each split into two triangles, wound outward; every
// vertex then pushed along its direction from `centre` by a factor in [0.6, 1.4] (star-shaped, so
// still closed and embedded, but not convex), and moved by `centre`.
void addStarShape(Mesh& mesh, int n, const Vec3& centre, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> radial(0.6, 1.4);
  std::map<std::tuple<int, int, int>, int> indexOf;  // lattice point → vertex (shared by sides)
  auto vertex = [&](int i, int j, int k) {
    const auto [it, fresh] = indexOf.emplace(std::tuple{i, j, k}, int(mesh.positions.size()));
    if (fresh) {
      const Vec3 p = Vec3(i, j, k) * (2.0 / n) - Vec3(1.0);
      mesh.positions.push_back(centre + p * radial(rng));
    }
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
          auto corner = [&](int da, int db) {
            int c[3];
            c[axis] = side * n;
            c[(axis + 1) % 3] = a + da;
            c[(axis + 2) % 3] = b + db;
            return vertex(c[0], c[1], c[2]);
          };
          // (axis+1) × (axis+2) = +axis: counter-clockwise seen from outside on the + side.
          IndexPolygon first{corner(0, 0), corner(1, 0), corner(1, 1)},
              second{corner(0, 0), corner(1, 1), corner(0, 1)};
          if (side == 0) {
            std::reverse(first.begin(), first.end());
            std::reverse(second.begin(), second.end());
          }
          mesh.faces.push_back(first);
          mesh.faces.push_back(second);
        }
}

// An open n × n grid of quads in the plane y = height, facing up.
void addGrid(Mesh& mesh, int n, double height) {
  const int first = int(mesh.positions.size());
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) mesh.positions.push_back(Vec3(i, height, j));
  auto at = [&](int i, int j) { return first + i * (n + 1) + j; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      mesh.faces.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
}

// Every directed edge used once, and each undirected edge by exactly two faces running opposite
// ways.
bool consistentlyClosed(const std::vector<IndexPolygon>& faces) {
  std::map<std::pair<int, int>, int> directed;
  for (const IndexPolygon& f : faces)
    for (size_t k = 0; k < f.size(); ++k) ++directed[{f[k], f[(k + 1) % f.size()]}];
  for (const auto& [edge, count] : directed)
    if (count != 1 || !directed.count({edge.second, edge.first})) return false;
  return true;
}

// No directed edge used twice (the open-surface form of "wound one way").
bool consistentlyWound(const std::vector<IndexPolygon>& faces) {
  std::set<std::pair<int, int>> directed;
  for (const IndexPolygon& f : faces)
    for (size_t k = 0; k < f.size(); ++k)
      if (!directed.insert({f[k], f[(k + 1) % f.size()]}).second) return false;
  return true;
}

double signedVolume(const std::vector<Vec3>& positions, const std::vector<IndexPolygon>& faces) {
  double sum = 0;
  for (const IndexPolygon& f : faces)
    for (size_t k = 1; k + 1 < f.size(); ++k)
      sum += glm::dot(positions[size_t(f[0])],
                      glm::cross(positions[size_t(f[k])], positions[size_t(f[k + 1])]));
  return sum / 6;
}

IndexPolygon reversed(IndexPolygon f) {
  std::reverse(f.begin(), f.end());
  return f;
}

TEST(MeshOrientation, SeededClosedShapesWithRandomFlipsComeBackOutward) {
  for (uint64_t seed = 1; seed <= 40; ++seed) {
    std::mt19937_64 rng(seed);
    Mesh mesh;
    const int shapes = 1 + int(rng() % 3);
    std::vector<size_t> firstFace;
    for (int s = 0; s < shapes; ++s) {
      firstFace.push_back(mesh.faces.size());
      addStarShape(mesh, 1 + int(rng() % 4), Vec3(5.0 * s, 0.5 * s, 0), rng);
    }
    firstFace.push_back(mesh.faces.size());
    const std::vector<IndexPolygon> original = mesh.faces;
    ASSERT_TRUE(consistentlyClosed(original));
    // A third of the faces flipped, or two thirds of a shape turned inside out: a closed shape's
    // outward winding is unique, so exactly these faces must be turned back.
    size_t flipped = 0;
    for (int s = 0; s < shapes; ++s) {
      const bool insideOut = rng() % 4 == 0;
      for (size_t f = firstFace[s]; f < firstFace[s + 1]; ++f) {
        const bool flip = (rng() % 3 == 0) != insideOut;
        if (flip) {
          mesh.faces[f] = reversed(mesh.faces[f]);
          ++flipped;
        }
      }
    }
    const SurfaceFacts facts = orientFaces(mesh.positions, mesh.faces, {});
    EXPECT_EQ(facts.components, size_t(shapes)) << "seed " << seed;
    EXPECT_EQ(facts.closedComponents, size_t(shapes)) << "seed " << seed;
    EXPECT_EQ(facts.nonManifoldEdges, 0u);
    EXPECT_EQ(facts.boundaryEdges, 0u);
    EXPECT_EQ(facts.facesFlipped, flipped)
        << "seed " << seed;  // exactly the flipped ones turned back
    EXPECT_EQ(mesh.faces, original) << "seed " << seed;
    for (int s = 0; s < shapes; ++s) {
      const std::vector<IndexPolygon> shape(mesh.faces.begin() + std::ptrdiff_t(firstFace[s]),
                                            mesh.faces.begin() + std::ptrdiff_t(firstFace[s + 1]));
      EXPECT_TRUE(consistentlyClosed(shape)) << "seed " << seed << " shape " << s;
      EXPECT_GT(signedVolume(mesh.positions, shape), 0) << "seed " << seed << " shape " << s;
    }
  }
}

TEST(MeshOrientation, SeededOpenGridsAreWoundOneWayWithTheFewerFlips) {
  for (uint64_t seed = 1; seed <= 40; ++seed) {
    std::mt19937_64 rng(seed);
    Mesh mesh;
    addGrid(mesh, 2 + int(rng() % 5), 0);
    size_t flipped = 0;
    for (IndexPolygon& f : mesh.faces)
      if (rng() % 2) {
        f = reversed(f);
        ++flipped;
      }
    const size_t faces = mesh.faces.size();
    const SurfaceFacts facts = orientFaces(mesh.positions, mesh.faces, {});
    EXPECT_TRUE(consistentlyWound(mesh.faces)) << "seed " << seed;
    EXPECT_EQ(facts.facesFlipped, std::min(flipped, faces - flipped)) << "seed " << seed;
    EXPECT_EQ(facts.components, 1u);
    EXPECT_EQ(facts.closedComponents, 0u);
    EXPECT_GT(facts.boundaryEdges, 0u);
  }
}

TEST(MeshOrientation, ClosedShapeAroundALightFacesInward) {
  std::mt19937_64 rng(7);
  Mesh room;
  addStarShape(room, 2, Vec3(0.0), rng);
  const std::vector<IndexPolygon> outward = room.faces;
  for (IndexPolygon& f : room.faces) f = reversed(f);  // inward, as a room is
  room.faces[3] = reversed(room.faces[3]);             // one face wrong
  const SurfaceFacts facts = orientFaces(room.positions, room.faces, {Vec3(0.0, 0.1, 0.0)});
  EXPECT_EQ(facts.closedComponentsAroundLights, 1u);
  EXPECT_EQ(facts.closedComponentsTurnedOutward, 0u);
  EXPECT_EQ(facts.facesFlipped, 1u);
  EXPECT_LT(signedVolume(room.positions, room.faces), 0);
  // The same shape with the light outside it: turned outward whole.
  Mesh box = room;
  const SurfaceFacts turned = orientFaces(box.positions, box.faces, {Vec3(10.0, 0, 0)});
  EXPECT_EQ(turned.closedComponentsTurnedOutward, 1u);
  EXPECT_EQ(turned.facesFlipped, box.faces.size());
  EXPECT_EQ(box.faces, outward);
}

TEST(MeshOrientation, WindingNumberOfACube) {
  std::mt19937_64 rng(1);
  Mesh cube;
  addStarShape(cube, 1, Vec3(0.0), rng);
  EXPECT_NEAR(windingNumber(cube.positions, cube.faces, Vec3(0.0)), 1, 1e-12);
  EXPECT_NEAR(windingNumber(cube.positions, cube.faces, Vec3(3, 0, 0)), 0, 1e-12);
}

TEST(MeshOrientation, NonManifoldEdgesAreCountedAndNotCrossed) {
  // Three pages of a book on one spine edge (0, 1), and a page that agrees with none.
  Mesh book;
  book.positions = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0},  {1, 1, 0},
                    {0, 0, 1}, {0, 1, 1}, {-1, 0, 0}, {-1, 1, 0}};
  book.faces = {{0, 2, 3, 1}, {0, 4, 5, 1}, {1, 7, 6, 0}};
  const SurfaceFacts before = surfaceFacts(book.faces);
  EXPECT_EQ(before.nonManifoldEdges, 1u);
  EXPECT_EQ(before.components, 3u);
  const std::vector<IndexPolygon> faces = book.faces;
  const SurfaceFacts facts = orientFaces(book.positions, book.faces, {});
  EXPECT_EQ(facts.nonManifoldEdges, 1u);
  EXPECT_EQ(facts.components, 3u);
  EXPECT_EQ(facts.closedComponents, 0u);
  EXPECT_EQ(facts.facesFlipped, 0u);  // nothing is decided across a non-manifold edge
  EXPECT_EQ(book.faces, faces);
}

TEST(MeshOrientation, TwoSidedSheetIsClosedButNotTurned) {
  Mesh sheet;
  sheet.positions = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
  sheet.faces = {{0, 1, 2, 3}, {3, 2, 1, 0}};
  const SurfaceFacts facts = orientFaces(sheet.positions, sheet.faces, {});
  EXPECT_EQ(facts.components, 1u);
  EXPECT_EQ(facts.closedComponents, 1u);
  EXPECT_EQ(facts.facesFlipped, 0u);
}

}  // namespace
}  // namespace penumbra::interchange
