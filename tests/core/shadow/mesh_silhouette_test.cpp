// A mesh's potential silhouette from a light polygon (mesh_silhouette.h), on seeded
// non-convex, open and inconsistently oriented meshes: what it leaves out is on no
// silhouette (an edge from its light vertex, a corner from every point of the light edge
// outside its stretch), and the per-thread memo answers as the silhouette computed alone,
// whatever was asked before; one receiver's own is the whole one's part in front of it
// (issue 35), and a light clipped by a receiver's plane gives the same among the whole light's
// candidates.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/geom/clip.h"
#include "core/shadow/mesh_silhouette.h"
#include "tests/core/illum/random_meshes.h"

namespace penumbra {
namespace {

// One mesh alone under a light, and what meshSilhouette() takes of it.
struct OneMesh {
  Scene scene;
  uint32_t handle() const { return scene.handleOf(0); }
  const MeshTopology& mesh() const { return *scene.meshTopology(handle()); }
  std::span<const Face> faces() const { return scene.facesOfObject(handle()); }
  double onPlane() const { return scene.tolerance().onPlane(); }
};

// Whether light point x is more than onPlane on one side of every face through corner v.
bool offEveryFaceAt(const OneMesh& one, uint32_t v, const Vec3& x) {
  const MeshTopology& mesh = one.mesh();
  const std::span<const Face> faces = one.faces();
  const double onPlane = one.onPlane();
  bool front = true, back = true;
  for (uint32_t k = mesh.vertexStarts[v]; k < mesh.vertexStarts[v + 1]; ++k) {
    const double d = faces[mesh.vertexFaces[k]].plane.signedDistance(x);
    front = front && d > onPlane, back = back && d < -onPlane;
  }
  return front || back;
}

bool sameCorners(const std::vector<MeshSilhouette::Corner>& a, const std::vector<MeshSilhouette::Corner>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(),
                    [](const auto& x, const auto& y) { return x.vertex == y.vertex && x.from == y.from && x.to == y.to; });
}

bool sameSilhouette(const MeshSilhouette& a, const MeshSilhouette& b) {
  if (a.edges != b.edges || a.corners.size() != b.corners.size()) return false;
  for (size_t i = 0; i < a.corners.size(); ++i)
    if (!sameCorners(a.corners[i], b.corners[i])) return false;
  return true;
}

TEST(MeshSilhouette, WhatItLeavesOutIsOnNoSilhouette) {
  size_t leftOutCorners = 0, keptCorners = 0, leftOutEdges = 0, checked = 0;
  for (uint64_t seed = 1; seed <= 3; ++seed)
    for (const test::NamedMesh& named : test::seededMeshes(seed)) {
      const Light light = test::ceilingLight(0.3 + 0.2 * double(seed));
      const OneMesh one{Scene({light}, {}, {named.mesh})};
      const MeshTopology& mesh = one.mesh();
      const std::span<const Face> faces = one.faces();
      const double onPlane = one.onPlane();
      const MeshSilhouette silhouette = meshSilhouette(faces, mesh, light.polygon, onPlane);
      const size_t n = light.polygon.size();
      std::mt19937_64 rng(seed);
      std::uniform_real_distribution<double> unit(0, 1);
      for (size_t i = 0; i < n; ++i) {
        const Vec3 p = light.polygon[i], q = light.polygon[(i + 1) % n];
        // An edge left out is regular with both faces' planes on one side of the light vertex.
        for (uint32_t e = 0; e < mesh.welded.edges.size(); ++e) {
          if (std::binary_search(silhouette.edges[i].begin(), silhouette.edges[i].end(), e)) continue;
          ASSERT_TRUE(mesh.regularEdge[e]) << named.name;
          const uint32_t* f = mesh.edgeFaces.data() + mesh.edgeStarts[e];
          const double a = faces[f[0]].plane.signedDistance(p), b = faces[f[1]].plane.signedDistance(p);
          EXPECT_TRUE((a > onPlane && b > onPlane) || (a < -onPlane && b < -onPlane)) << named.name << " edge " << e;
          ++leftOutEdges;
        }
        // A corner is off every face through it from the points of pq outside its stretch
        // (all of pq for a corner left out).
        std::vector<double> from(mesh.welded.vertices.size(), 1), to(mesh.welded.vertices.size(), 0);
        for (const auto& c : silhouette.corners[i]) from[c.vertex] = c.from, to[c.vertex] = c.to, ++keptCorners;
        for (uint32_t v = 0; v < mesh.welded.vertices.size(); ++v) {
          leftOutCorners += from[v] > to[v];
          for (int k = 0; k < 6; ++k) {
            const double t = unit(rng);
            if (from[v] <= t && t <= to[v]) continue;
            EXPECT_TRUE(offEveryFaceAt(one, v, p + t * (q - p)))
                << named.name << " corner " << v << " at " << t;
            ++checked;
          }
        }
      }
    }
  // Both kinds are exercised: corners left out, kept over a stretch, edges left out.
  EXPECT_GT(leftOutCorners, 1000u);
  EXPECT_GT(keptCorners, 1000u);
  EXPECT_GT(leftOutEdges, 1000u);
  EXPECT_GT(checked, 10000u);
}

// For one receiver (a clipped light is its own): the whole silhouette's part in front of its plane.
TEST(MeshSilhouette, AReceiversOwnIsTheWholeOnesPartInFrontOfIt) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  size_t kept = 0, dropped = 0;
  for (const test::NamedMesh& named : test::seededMeshes(2)) {
    const Light light = test::ceilingLight(0.6);
    const OneMesh one{Scene({light}, {}, {named.mesh})};
    const MeshTopology& mesh = one.mesh();
    const std::span<const Face> faces = one.faces();
    const double onPlane = one.onPlane();
    const MeshSilhouette whole = meshSilhouette(faces, mesh, light.polygon, onPlane);
    for (int k = 0; k < 10; ++k) {
      // A plane through the mesh's middle at a random tilt, as one of its own faces' planes.
      const Plane receiver = Plane::throughPoint(glm::normalize(Vec3(u(rng), u(rng), u(rng))), Vec3(0, 1.3, 0));
      std::vector<double> ahead;
      for (const Vec3& v : mesh.welded.vertices) ahead.push_back(receiver.signedDistance(v));
      const MeshSilhouette own = meshSilhouette(faces, mesh, light.polygon, onPlane, ahead);
      MeshSilhouette expected = whole;
      for (size_t i = 0; i < expected.edges.size(); ++i) {
        std::erase_if(expected.edges[i], [&](uint32_t e) {
          return !(ahead[mesh.welded.edges[e].first] > onPlane) && !(ahead[mesh.welded.edges[e].second] > onPlane);
        });
        std::erase_if(expected.corners[i], [&](const MeshSilhouette::Corner& c) { return !(ahead[c.vertex] > onPlane); });
        kept += expected.corners[i].size(), dropped += whole.corners[i].size() - expected.corners[i].size();
      }
      EXPECT_TRUE(sameSilhouette(own, expected)) << named.name << " plane " << k;
    }
  }
  EXPECT_GT(kept, 100u);
  EXPECT_GT(dropped, 100u);
}

// A light clipped by a receiver's plane (a model's face whose plane cuts it): tested only among
// the whole light's candidates, it gives what the whole scan gives for every part the receiver
// uses, bit for bit, and drops most of the mesh from the scan.
TEST(MeshSilhouette, AClippedLightTestsOnlyTheWholeLightsCandidates) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  size_t clipped = 0, edges = 0, corners = 0;
  for (uint64_t seed = 1; seed <= 3; ++seed)
    for (const test::NamedMesh& named : test::seededMeshes(seed)) {
      const Light light = test::ceilingLight(0.4 + 0.2 * double(seed));
      const OneMesh one{Scene({light}, {}, {named.mesh})};
      const MeshTopology& mesh = one.mesh();
      const std::span<const Face> faces = one.faces();
      const double onPlane = one.onPlane(), eps = one.scene.tolerance().length();
      for (int k = 0; k < 12; ++k) {
        // A steep plane through a point under the light, cutting it; every fourth through a
        // light corner.
        const Vec3 normal = glm::normalize(Vec3(u(rng), 0.3 * u(rng), u(rng)));
        const Vec3 through = k % 4 == 3 ? light.polygon[k % light.polygon.size()]
                                        : Vec3(0.5 * u(rng), 1.3 + 0.3 * u(rng), 0.5 * u(rng));
        const Plane receiver = Plane::throughPoint(normal, through);
        const Polygon3 s = clipFront(light.polygon, receiver, eps);
        if (s.size() < 3) continue;
        ++clipped;
        std::vector<double> ahead;
        for (const Vec3& v : mesh.welded.vertices) ahead.push_back(receiver.signedDistance(v));
        std::vector<uint8_t> on;
        for (const Vec3& x : s) on.push_back(std::abs(receiver.signedDistance(x)) <= eps);
        const MeshSilhouette all = meshSilhouette(faces, mesh, s, onPlane, ahead);
        const MeshSilhouette own = clippedMeshSilhouette(faces, mesh, light.polygon, s, onPlane, ahead, on, eps);
        const size_t n = s.size();
        for (size_t i = 0; i < n; ++i) {
          if (!on[i]) {
            EXPECT_EQ(own.edges[i], all.edges[i]) << named.name << " plane " << k << " light vertex " << i;
            edges += all.edges[i].size();
          } else {
            EXPECT_TRUE(own.edges[i].empty());
          }
          if (!on[i] || !on[(i + 1) % n]) {
            EXPECT_TRUE(sameCorners(own.corners[i], all.corners[i])) << named.name << " plane " << k << " light edge " << i;
            corners += all.corners[i].size();
          } else {
            EXPECT_TRUE(own.corners[i].empty());
          }
        }
      }
    }
  EXPECT_GT(clipped, 100u);
  EXPECT_GT(edges, 1000u);
  EXPECT_GT(corners, 300u);
}

TEST(MeshSilhouette, TheMemoAnswersAsTheSilhouetteAloneWhateverWasAskedBefore) {
  struct Asked {
    size_t scene, light;
  };
  std::vector<OneMesh> meshes;
  for (const test::NamedMesh& named : test::seededMeshes(4)) meshes.push_back({Scene({test::ceilingLight(0.5)}, {}, {named.mesh})});
  std::vector<Polygon3> lights;
  for (double half : {0.3, 0.5, 0.8}) lights.push_back(test::ceilingLight(half).polygon);
  std::vector<Asked> order;
  for (size_t s = 0; s < meshes.size(); ++s)
    for (size_t l = 0; l < lights.size(); ++l) order.push_back({s, l});
  std::mt19937_64 rng(5);
  for (int round = 0; round < 3; ++round) {
    std::shuffle(order.begin(), order.end(), rng);
    for (const Asked& a : order) {
      const OneMesh& one = meshes[a.scene];
      const std::span<const Face> faces = one.faces();
      const MeshTopology& mesh = one.mesh();
      const double onPlane = one.onPlane();
      EXPECT_TRUE(sameSilhouette(memoisedMeshSilhouette(faces, mesh, lights[a.light], onPlane),
                                 meshSilhouette(faces, mesh, lights[a.light], onPlane)))
          << "mesh " << a.scene << " light " << a.light << " round " << round;
    }
  }
}

}  // namespace
}  // namespace penumbra
