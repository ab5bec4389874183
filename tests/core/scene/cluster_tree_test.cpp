// The clusters' ball tree (MeshTopology::clusterTree, issue 35): its leaves are the clusters in
// order with their own balls, each node's ball holds its children's, and a pass through it
// (forEachClusterMeeting) visits exactly the clusters a pass over every cluster keeps, on
// seeded closed, open and flipped meshes and a 20 k-face sphere, for planes and boxes placed at
// random and planes set tangent to a cluster's ball to the last bits.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/scene/mesh_topology.h"
#include "tests/core/illum/random_meshes.h"

namespace penumbra {
namespace {

std::vector<Object> meshesOf(uint64_t seed) {
  std::vector<Object> out;
  for (const test::NamedMesh& named : test::seededMeshes(seed)) out.push_back(named.mesh);
  out.push_back(test::bumpySphere("big", {0.3, 1.1, 0.2}, 0.6, 100, 0.05, seed));  // ~20 k faces
  return out;
}

// The clusters a pass over every cluster keeps, and those the tree visits.
template <class Misses>
void bothPasses(const MeshTopology& mesh, const Misses& misses, std::vector<uint32_t>& every,
                std::vector<uint32_t>& tree) {
  every.clear();
  tree.clear();
  for (uint32_t c = 0; c < mesh.clusters.size(); ++c)
    if (!misses(mesh.clusters[c])) every.push_back(c);
  mesh.forEachClusterMeeting(misses, [&](uint32_t c) {
    tree.push_back(c);
    return true;
  });
}

TEST(ClusterTree, NodesHoldTheirChildrenAndLeavesAreTheClustersInOrder) {
  for (uint64_t seed = 1; seed <= 3; ++seed)
    for (const Object& object : meshesOf(seed)) {
      const Scene scene({test::ceilingLight(0.5)}, {}, {object});
      const MeshTopology& mesh = *scene.meshTopology(scene.handleOf(0));
      ASSERT_FALSE(mesh.clusterTree.empty());
      EXPECT_EQ(mesh.clusterTree.size(), 2 * mesh.clusters.size() - 1);
      uint32_t nextLeaf = 0;
      for (size_t i = 0; i < mesh.clusterTree.size(); ++i) {
        const MeshTopology::ClusterNode& node = mesh.clusterTree[i];
        ASSERT_LT(node.firstCluster, node.endCluster);
        EXPECT_EQ(node.ball.first, mesh.clusters[node.firstCluster].first);
        EXPECT_EQ(node.ball.last, mesh.clusters[node.endCluster - 1].last);
        if (node.endCluster - node.firstCluster == 1) {
          EXPECT_EQ(node.firstCluster, nextLeaf++);
          EXPECT_EQ(node.skip, i + 1);
          EXPECT_EQ(node.ball.centre, mesh.clusters[node.firstCluster].centre);
          EXPECT_EQ(node.ball.radius, mesh.clusters[node.firstCluster].radius);
          continue;
        }
        // Its subtree is [i + 1, skip) and its clusters are its leaves'.
        ASSERT_GT(node.skip, i + 1);
        ASSERT_LE(node.skip, mesh.clusterTree.size());
        for (size_t j = i + 1; j < node.skip; ++j) {
          const MeshTopology::ClusterNode& inner = mesh.clusterTree[j];
          EXPECT_GE(inner.firstCluster, node.firstCluster);
          EXPECT_LE(inner.endCluster, node.endCluster);
          EXPECT_LE(glm::length(inner.ball.centre - node.ball.centre) + inner.ball.radius, node.ball.radius);
        }
      }
      EXPECT_EQ(nextLeaf, mesh.clusters.size());
    }
}

TEST(ClusterTree, VisitsExactlyWhatAPassOverEveryClusterKeeps) {
  size_t compared = 0, partial = 0, tangent = 0;
  std::vector<uint32_t> every, tree;
  for (uint64_t seed = 1; seed <= 3; ++seed)
    for (const Object& object : meshesOf(seed)) {
      const Scene scene({test::ceilingLight(0.5)}, {}, {object});
      const MeshTopology& mesh = *scene.meshTopology(scene.handleOf(0));
      std::mt19937_64 rng(seed * 7919 + mesh.clusters.size());
      std::uniform_real_distribution<double> u(-1, 1), unit(0, 1);
      std::uniform_int_distribution<size_t> anyCluster(0, mesh.clusters.size() - 1);
      for (int trial = 0; trial < 200; ++trial) {
        // Up to four planes (a cone's sides, a receiver's plane), the ball outside one of them.
        std::vector<Plane> planes;
        const int count = 1 + trial % 4;
        for (int k = 0; k < count; ++k) {
          const Vec3 normal = glm::normalize(Vec3(u(rng), u(rng), u(rng)));
          const Vec3 through = Vec3(0.1, 1.2, 0) + 0.6 * Vec3(u(rng), u(rng), u(rng));
          Plane plane = Plane::throughPoint(normal, through);
          if (trial % 3 == 0) {  // tangent to a cluster's ball, to the last bits
            const MeshTopology::Cluster& c = mesh.clusters[anyCluster(rng)];
            plane = Plane::throughPoint(normal, c.centre + (c.radius + 1e-9) * normal);
            plane.offset = std::nextafter(plane.offset, trial % 2 ? INFINITY : -INFINITY);
            ++tangent;
          }
          planes.push_back(plane);
        }
        const double margin = 1e-9;
        const auto beyondAPlane = [&](const MeshTopology::Cluster& ball) {
          for (const Plane& plane : planes)
            if (plane.signedDistance(ball.centre) < -(ball.radius + margin)) return true;
          return false;
        };
        bothPasses(mesh, beyondAPlane, every, tree);
        ASSERT_EQ(tree, every) << "seed " << seed << " trial " << trial;
        // Within a reach of a box (nearFaces' test).
        const Vec3 low = Vec3(0.1, 1.2, 0) + 0.7 * Vec3(u(rng), u(rng), u(rng));
        const Vec3 high = low + 0.3 * Vec3(unit(rng), unit(rng), unit(rng));
        const double reach = 0.05 * unit(rng);
        const auto away = [&](const MeshTopology::Cluster& ball) {
          const Vec3 outside = glm::max(low - ball.centre, glm::max(ball.centre - high, Vec3(0.0)));
          const double within = ball.radius + reach;
          return glm::dot(outside, outside) > within * within;
        };
        bothPasses(mesh, away, every, tree);
        ASSERT_EQ(tree, every) << "seed " << seed << " trial " << trial << " (box)";
        compared += 2;
        partial += !every.empty() && every.size() < mesh.clusters.size();
      }
      // Stopping: visit returning false ends the pass.
      size_t visited = 0;
      mesh.forEachClusterMeeting([](const MeshTopology::Cluster&) { return false; },
                                 [&](uint32_t) { return ++visited < 3; });
      EXPECT_EQ(visited, std::min<size_t>(3, mesh.clusters.size()));
    }
  EXPECT_GT(compared, 2000u);
  EXPECT_GT(partial, 1000u);
  EXPECT_GT(tangent, 500u);
}

}  // namespace
}  // namespace penumbra
