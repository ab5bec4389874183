// The procedural model meshes (scenegen/*_mesh.h), seeded, at several sizes: triangle count
// within ±25 % of the request, welded (no two vertices at one position, no repeated corner),
// every directed edge at most once and — closed models — its reverse exactly once, one
// component, positive signed volume; outward orientation checked at extreme vertices; the
// teapot open only along the six loops its header names; the bowl open only at its rim.
// Edges are counted here with a map of our own, not with tri_mesh's meshEdges (which is
// checked on its own against a tetrahedron).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "scenegen/blob_mesh.h"
#include "scenegen/bowl_mesh.h"
#include "scenegen/scan_mesh.h"
#include "scenegen/teapot_mesh.h"
#include "scenegen/torus_knot_mesh.h"

namespace penumbra {
namespace {

using Edge = std::pair<int, int>;

// Directed edge → uses.
std::map<Edge, int> directedEdges(const TriMesh& mesh) {
  std::map<Edge, int> out;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++out[{t[size_t(k)], t[size_t((k + 1) % 3)]}];
  return out;
}

// Directed edges whose reverse no triangle has (the open boundary).
std::vector<Edge> boundaryEdges(const TriMesh& mesh) {
  const auto edges = directedEdges(mesh);
  std::vector<Edge> out;
  for (const auto& [e, uses] : edges)
    if (!edges.count({e.second, e.first})) out.push_back(e);
  return out;
}

void expectWelded(const TriMesh& mesh, const std::string& what) {
  std::set<std::tuple<double, double, double>> positions;
  for (const Vec3& v : mesh.vertices) positions.insert({v.x, v.y, v.z});
  EXPECT_EQ(positions.size(), mesh.vertices.size()) << what << ": two vertices at one position";
  std::vector<bool> used(mesh.vertices.size(), false);
  for (const auto& t : mesh.triangles) {
    EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) << what << ": a repeated corner";
    for (int i : t) used[size_t(i)] = true;
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0) << what << ": unused vertices";
}

// Each directed edge at most once; with `closed`, also its reverse exactly once.
void expectEdges(const TriMesh& mesh, bool closed, const std::string& what) {
  const auto edges = directedEdges(mesh);
  size_t repeated = 0, unpaired = 0;
  for (const auto& [e, uses] : edges) {
    repeated += uses > 1;
    unpaired += !edges.count({e.second, e.first});
  }
  EXPECT_EQ(repeated, 0u) << what << ": directed edges used twice (orientation breaks)";
  if (closed) {
    EXPECT_EQ(unpaired, 0u) << what << ": open edges";
  }
}

double signedVolumeOf(const TriMesh& mesh) {
  double sum = 0;
  for (const auto& t : mesh.triangles)
    sum += glm::determinant(glm::dmat3(mesh.vertices[size_t(t[0])], mesh.vertices[size_t(t[1])],
                                       mesh.vertices[size_t(t[2])]));
  return sum / 6;
}

// Components joined through shared edges.
size_t components(const TriMesh& mesh, std::vector<int>* labelOut = nullptr) {
  std::vector<int> parent(mesh.triangles.size());
  for (size_t i = 0; i < parent.size(); ++i) parent[i] = int(i);
  auto find = [&](int i) {
    while (parent[size_t(i)] != i) i = parent[size_t(i)] = parent[size_t(parent[size_t(i)])];
    return i;
  };
  std::map<Edge, int> firstFace;
  for (size_t f = 0; f < mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      int a = mesh.triangles[f][size_t(k)], b = mesh.triangles[f][size_t((k + 1) % 3)];
      if (a > b) std::swap(a, b);
      const auto [it, inserted] = firstFace.emplace(Edge{a, b}, int(f));
      if (!inserted) parent[size_t(find(int(f)))] = find(it->second);
    }
  std::set<int> roots;
  for (size_t f = 0; f < parent.size(); ++f) roots.insert(find(int(f)));
  if (labelOut) {
    labelOut->resize(parent.size());
    for (size_t f = 0; f < parent.size(); ++f) (*labelOut)[f] = find(int(f));
  }
  return roots.size();
}

// For each component and each axis direction d whose extreme vertex is not on the open
// boundary: the area-weighted normal of the faces round that vertex points along d (an
// outward surface faces away from its inside where it is outermost). Returns the checks made.
int expectOutwardAtExtremes(const TriMesh& mesh, const std::string& what) {
  std::vector<int> label;
  components(mesh, &label);
  std::set<int> onBoundary;
  for (const Edge& e : boundaryEdges(mesh)) onBoundary.insert({e.first, e.second});
  std::map<int, std::vector<size_t>> faces;  // component → faces
  for (size_t f = 0; f < label.size(); ++f) faces[label[f]].push_back(f);
  int checks = 0;
  for (const auto& [component, members] : faces) {
    int checked = 0;
    for (const Vec3& d : {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0),
                          Vec3(0, 0, 1), Vec3(0, 0, -1)}) {
      // The outermost vertex; among equals one off the open boundary if there is one.
      int extreme = -1;
      for (size_t f : members)
        for (int v : mesh.triangles[f]) {
          if (extreme < 0) {
            extreme = v;
            continue;
          }
          const double a = glm::dot(mesh.vertices[size_t(v)], d),
                       b = glm::dot(mesh.vertices[size_t(extreme)], d);
          if (a > b || (a == b && onBoundary.count(extreme) && !onBoundary.count(v))) extreme = v;
        }
      if (onBoundary.count(extreme)) continue;
      Vec3 normal(0.0);
      for (size_t f : members) {
        const auto& t = mesh.triangles[f];
        if (t[0] != extreme && t[1] != extreme && t[2] != extreme) continue;
        const Vec3 &a = mesh.vertices[size_t(t[0])], &b = mesh.vertices[size_t(t[1])],
                   &c = mesh.vertices[size_t(t[2])];
        normal += glm::cross(b - a, c - a);
      }
      EXPECT_GT(glm::dot(normal, d), 0)
          << what << ": component " << component << " faces inward along " << d.x << "," << d.y
          << "," << d.z;
      ++checked;
    }
    // (The teapot's lid is outermost only at its knob: its widest and lowest points are on its
    // rim.)
    EXPECT_GE(checked, 1) << what << ": component " << component << " has no interior extreme";
    checks += checked;
  }
  return checks;
}

void expectCountNear(size_t made, int asked, const std::string& what) {
  EXPECT_GE(double(made), 0.75 * asked) << what;
  EXPECT_LE(double(made), 1.25 * asked) << what;
}

// A closed model: welded, watertight, consistently oriented, one piece, outward.
void expectClosedModel(const TriMesh& mesh, int asked, const std::string& what) {
  expectCountNear(mesh.triangles.size(), asked, what);
  expectWelded(mesh, what);
  expectEdges(mesh, true, what);
  EXPECT_EQ(components(mesh), 1u) << what;
  EXPECT_GT(signedVolumeOf(mesh), 0) << what;
  expectOutwardAtExtremes(mesh, what);
}

TEST(TriMesh, WeldsDropsCollapsedAndCountsEdges) {
  // A tetrahedron given as a soup with repeated positions and one collapsed triangle.
  const std::vector<Vec3> soup{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1},   {1, 0, 0},
                               {0, 1, 0}, {0, 0, 1}, {0, 0, 0}, {-0.0, 0, 0}};
  TriMesh mesh = weldedMesh(soup, {{0, 2, 1}, {7, 4, 3}, {8, 6, 5}, {1, 2, 3}, {0, 8, 4}});
  EXPECT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.triangles.size(), 4u);  // {0, 8, 4} collapses: 0 and −0 are one position
  MeshEdges edges = meshEdges(mesh);
  EXPECT_TRUE(edges.closed());
  EXPECT_EQ(edges.edges, 6u);
  EXPECT_NEAR(signedVolume(mesh), 1.0 / 6, 1e-15);
  mesh.triangles[3] = {mesh.triangles[3][0], mesh.triangles[3][2], mesh.triangles[3][1]};
  edges = meshEdges(mesh);
  EXPECT_FALSE(edges.consistent());
  EXPECT_EQ(edges.repeated, 3u);
  mesh.triangles.pop_back();
  edges = meshEdges(mesh);
  EXPECT_EQ(edges.boundary, 3u);
  EXPECT_TRUE(edges.consistent());
  EXPECT_FALSE(edges.closed());
}

TEST(TeapotMesh, StepsAndCounts) {
  EXPECT_EQ(teapotStepsFor(1000).u, 4);
  EXPECT_EQ(teapotStepsFor(1000).v, 4);
  EXPECT_EQ(teapotStepsFor(6000).u, 10);
  EXPECT_EQ(teapotStepsFor(6000).v, 10);
  EXPECT_EQ(teapotTriangleCount({10, 10}), 6320u);
  for (int asked : {200, 300, 450, 1000, 2500, 6000, 20000, 70000}) {
    const TeapotSteps steps = teapotStepsFor(asked);
    EXPECT_LE(std::abs(steps.u - steps.v), 1) << asked;
    expectCountNear(teapotTriangleCount(steps), asked, "teapot " + std::to_string(asked));
  }
}

// The teapot at square and uneven steps: every triangle of the grid but the pole ones, welded,
// consistent, outward per component (body, lid, handle, spout), open only along the six loops.
TEST(TeapotMesh, WeldedOutwardAndOpenOnlyWhereTheHeaderSays) {
  for (const TeapotSteps steps :
       {TeapotSteps{2, 2}, TeapotSteps{3, 4}, TeapotSteps{4, 3}, TeapotSteps{10, 10}}) {
    const std::string what = "teapot " + std::to_string(steps.u) + "x" + std::to_string(steps.v);
    const TriMesh mesh = teapotMesh(steps);
    EXPECT_EQ(mesh.triangles.size(), teapotTriangleCount(steps)) << what;
    expectWelded(mesh, what);
    expectEdges(mesh, false, what);
    EXPECT_EQ(components(mesh), 4u) << what;  // body with bottom, lid, handle, spout
    EXPECT_GE(expectOutwardAtExtremes(mesh, what), 8) << what;
    EXPECT_GT(signedVolumeOf(mesh), 0) << what;
    const MeshBounds bounds = meshBounds(mesh);
    EXPECT_EQ(bounds.min.y, 0.0) << what;
    EXPECT_DOUBLE_EQ(bounds.max.y, 3.15) << what;

    // Open edges (y up, patch units): walk them into loops and place each.
    const auto open = boundaryEdges(mesh);
    std::map<int, int> next;
    for (const Edge& e : open) {
      EXPECT_TRUE(next.emplace(e.first, e.second).second)
          << what << ": a boundary vertex opens twice";
    }
    int rim = 0, lidRim = 0, handle = 0, spoutBase = 0, spoutTip = 0;
    std::set<int> seen;
    for (const auto& [start, unused] : next) {
      if (seen.count(start)) continue;
      std::vector<Vec3> loop;
      for (int v = start; !seen.count(v); v = next.at(v)) {
        seen.insert(v);
        loop.push_back(mesh.vertices[size_t(v)]);
      }
      auto all = [&](auto predicate) { return std::all_of(loop.begin(), loop.end(), predicate); };
      auto radius = [](const Vec3& p) { return std::hypot(p.x, p.z); };
      if (all([&](const Vec3& p) {
            return std::abs(p.y - 2.4) < 1e-12 && std::abs(radius(p) - 1.4) < 0.02;
          }))
        ++rim;
      else if (all([&](const Vec3& p) {
                 return std::abs(p.y - 2.4) < 1e-12 && std::abs(radius(p) - 1.3) < 0.02;
               }))
        ++lidRim;
      else if (all([](const Vec3& p) { return p.x < -1.4; }))
        ++handle;
      else if (all([](const Vec3& p) { return std::abs(p.x - 1.7) < 1e-12; }))
        ++spoutBase;
      else if (all([](const Vec3& p) { return p.x >= 2.8 - 1e-12; }))
        ++spoutTip;
      else
        ADD_FAILURE() << what << ": an open loop the header does not name, at " << loop[0].x << ", "
                      << loop[0].y << ", " << loop[0].z;
    }
    EXPECT_EQ(rim, 1) << what;
    EXPECT_EQ(lidRim, 1) << what;
    EXPECT_EQ(handle, 2) << what;
    EXPECT_EQ(spoutBase, 1) << what;
    EXPECT_EQ(spoutTip, 1) << what;
  }
  EXPECT_THROW(teapotMesh({0, 3}), std::invalid_argument);
}

TEST(TorusKnotMesh, ClosedOutwardAtEverySize) {
  for (int asked : {200, 1000, 6000, 20000}) {
    const TriMesh mesh = torusKnotMesh({.triangles = asked});
    expectClosedModel(mesh, asked, "torus knot " + std::to_string(asked));
  }
  EXPECT_THROW(torusKnotMesh({.tubeRadius = 0.6}), std::invalid_argument);
  EXPECT_THROW(torusKnotMesh({.triangles = 10}), std::invalid_argument);
}

TEST(BlobMesh, SeededClosedOutwardAtEverySize) {
  for (uint64_t seed : {1u, 2u, 7u})
    for (int asked : {200, 1000, 6000}) {
      const std::string what = "blob seed " + std::to_string(seed) + " " + std::to_string(asked);
      const TriMesh mesh = blobMesh({.triangles = asked, .seed = seed});
      expectClosedModel(mesh, asked, what);
      // The same seed gives the same blob; another seed another one.
      const TriMesh again = blobMesh({.triangles = asked, .seed = seed});
      EXPECT_EQ(again.vertices, mesh.vertices) << what;
      EXPECT_NE(blobMesh({.triangles = asked, .seed = seed + 100}).vertices, mesh.vertices) << what;
    }
  EXPECT_THROW(blobMesh({.triangles = 50}), std::invalid_argument);
  EXPECT_THROW(blobMesh({.balls = 0}), std::invalid_argument);
}

TEST(ScanMesh, SeededClosedOutwardAt70k) {
  for (int asked : {200, 6000, 70000}) {
    const std::string what = "scan " + std::to_string(asked);
    const TriMesh mesh = scanMesh({.triangles = asked, .seed = 3});
    expectClosedModel(mesh, asked, what);
    // Sphere topology: V − E + F = 2.
    EXPECT_EQ(long(mesh.vertices.size()) - long(directedEdges(mesh).size() / 2) +
                  long(mesh.triangles.size()),
              2)
        << what;
  }
  EXPECT_NE(scanMesh({.triangles = 500, .seed = 1}).vertices,
            scanMesh({.triangles = 500, .seed = 2}).vertices);
}

// One sheet facing the sphere's centre (up into the bowl), open only along its rim at y = 0.
TEST(BowlMesh, OpenAtTheRimOnlyFacingIn) {
  for (int asked : {200, 1000, 6000}) {
    const std::string what = "bowl " + std::to_string(asked);
    const TriMesh mesh = bowlMesh(asked);
    expectCountNear(mesh.triangles.size(), asked, what);
    expectWelded(mesh, what);
    expectEdges(mesh, false, what);
    EXPECT_EQ(components(mesh), 1u) << what;
    const auto open = boundaryEdges(mesh);
    EXPECT_FALSE(open.empty()) << what;
    for (const Edge& e : open) {
      EXPECT_EQ(mesh.vertices[size_t(e.first)].y, 0.0) << what;
      EXPECT_EQ(mesh.vertices[size_t(e.second)].y, 0.0) << what;
    }
    for (const auto& t : mesh.triangles) {
      const Vec3 &a = mesh.vertices[size_t(t[0])], &b = mesh.vertices[size_t(t[1])],
                 &c = mesh.vertices[size_t(t[2])];
      ASSERT_GT(glm::dot(glm::cross(b - a, c - a), -(a + b + c) / 3.0), 0)
          << what << ": a face turned out";
    }
  }
}

}  // namespace
}  // namespace penumbra
