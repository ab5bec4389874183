// Vertex welding: positions within eps are one vertex, first seen wins; seeded clouds agree
// with a brute-force weld; extreme positions (1e18 cells away) weld without overflow.
#include <gtest/gtest.h>

#include <random>

#include "interchange/vertex_weld.h"

namespace penumbra::interchange {
namespace {

// The same rule by brute force: each position joins the first earlier distinct one within eps.
std::vector<int> bruteForceRemap(const std::vector<Vec3>& positions, double eps) {
  std::vector<int> remap(positions.size());
  std::vector<Vec3> distinct;
  for (size_t i = 0; i < positions.size(); ++i) {
    int found = -1;
    for (size_t j = 0; j < distinct.size() && found < 0; ++j) {
      const Vec3 d = glm::abs(distinct[j] - positions[i]);
      if (d.x <= eps && d.y <= eps && d.z <= eps) found = int(j);
    }
    if (found < 0) {
      found = int(distinct.size());
      distinct.push_back(positions[i]);
    }
    remap[i] = found;
  }
  return remap;
}

TEST(VertexWeld, SeededCloudsAgreeWithBruteForce) {
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> coordinate(-1, 1), jitter(-4e-7, 4e-7);
    std::vector<Vec3> positions;
    for (int i = 0; i < 300; ++i) {
      if (!positions.empty() && rng() % 3 == 0) {  // a near-duplicate of an earlier one
        const Vec3 p = positions[rng() % positions.size()];
        positions.push_back(p + Vec3(jitter(rng), jitter(rng), jitter(rng)));
      } else {
        positions.push_back({coordinate(rng), coordinate(rng), coordinate(rng)});
      }
    }
    // Random points lie far apart at this eps: each near-duplicate has one candidate, so the
    // grid search order cannot matter.
    const WeldResult weld = weldVertices(positions, 1e-6);
    EXPECT_EQ(weld.remap, bruteForceRemap(positions, 1e-6)) << "seed " << seed;
  }
}

// A fuzz finding (crashes/gltf_import/weld-cell-overflow.glb): an unused vertex 1e9 m away from
// a model a few nanometres across put its grid cell past int64 (UBSan: float→int overflow).
TEST(VertexWeld, FarPositionsWithATinyEpsWeldWithoutOverflow) {
  const std::vector<Vec3> positions = {{0, 0, 0}, {1e9, -1e9, 1e9}, {1e-30, 0, 0}, {1e9, -1e9, 1e9}, {-1e9, 0, 0}};
  const WeldResult weld = weldVertices(positions, 1e-25);
  EXPECT_EQ(weld.remap, (std::vector<int>{0, 1, 0, 1, 2}));
  EXPECT_EQ(weld.merged, 2u);
}

}  // namespace
}  // namespace penumbra::interchange
