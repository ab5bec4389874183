// The part diff of one frame (server/part_diff.h) over seeded random parts, each made in a known
// case: the same mesh object, an equal copy, new irradiance on the same shape, a new shape, a part
// new to the frame, and one that was not meshed again. The versions carried and the parts that
// left must follow the case; removals keep their order, drop parts live again, add the parts that
// left at the frame's version and forget those older than the since window.
#include "server/part_diff.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <random>
#include <set>
#include <string>

#include "server/limits.h"

namespace penumbra::server {
namespace {

enum class Case { SameObject, EqualCopy, NewIrradiance, NewShape, New, Left };

std::shared_ptr<const ReceiverMesh> someMesh(std::mt19937& rng) {
  auto mesh = std::make_shared<ReceiverMesh>();
  mesh->normal = Vec3(0, 0, 1);
  for (int i = 0; i < 3; ++i) {
    mesh->positions.push_back(Vec3(double(rng() % 100), double(rng() % 100), 0));
    mesh->irradiance.push_back(Vec3(double(rng() % 100)));
    mesh->classes.push_back(LightClass::Lit);
  }
  mesh->triangles.push_back({0, 1, 2});
  return mesh;
}

TEST(PartDiff, VersionsFollowWhatChangedAndTheRestLeft) {
  std::mt19937 rng(20261129);
  for (int round = 0; round < 200; ++round) {
    const uint64_t version = 10 + rng() % 50;
    std::vector<MeshPart> previous, next;
    std::vector<Case> cases;
    const int count = 1 + int(rng() % 12);
    for (int i = 0; i < count; ++i) {
      const PartKey key{{"object_" + std::to_string(rng() % 4), uint32_t(rng() % 3)},
                        int64_t(i),
                        int64_t(rng() % 3)};
      const Case c = Case(rng() % 6);
      const uint64_t shapeVersion = 1 + rng() % 5;
      const MeshPart old{key, someMesh(rng), shapeVersion + rng() % 4, shapeVersion};
      if (c != Case::New) previous.push_back(old);
      auto changed = std::make_shared<ReceiverMesh>(*old.mesh);
      if (c == Case::NewIrradiance) changed->irradiance[rng() % 3].y += 1;
      if (c == Case::NewShape) changed->positions[rng() % 3].x += 1;
      if (c == Case::SameObject)
        next.push_back({key, old.mesh, version, version});
      else if (c != Case::Left)
        next.push_back({key, std::move(changed), version, version});
      cases.push_back(c);
    }
    std::map<PartKey, const MeshPart*> before;
    for (const MeshPart& part : previous) before.emplace(part.key, &part);
    std::vector<MeshPart*> fresh;
    for (MeshPart& part : next) fresh.push_back(&part);
    const std::vector<PartKey> left = carryPartVersions(before, fresh);

    std::vector<PartKey> expectedLeft;
    size_t p = 0, n = 0;
    for (const Case c : cases) {
      const MeshPart* old = c == Case::New ? nullptr : &previous[p++];
      if (c == Case::Left) {
        expectedLeft.push_back(old->key);
        continue;
      }
      const MeshPart& part = next[n++];
      const bool keepsAll = c == Case::SameObject || c == Case::EqualCopy;
      const bool keepsShape = keepsAll || c == Case::NewIrradiance;
      EXPECT_EQ(part.version, keepsAll ? old->version : version) << "round " << round;
      EXPECT_EQ(part.shapeVersion, keepsShape ? old->shapeVersion : version) << "round " << round;
    }
    std::sort(expectedLeft.begin(), expectedLeft.end());
    EXPECT_EQ(left, expectedLeft) << "round " << round;
  }
}

TEST(PartDiff, RemovalsDropPartsLiveAgainAddThoseThatLeftAndForgetOldOnes) {
  std::mt19937 rng(7);
  for (int round = 0; round < 200; ++round) {
    const uint64_t version = kSinceWindow - 20 + rng() % 60;
    SceneSnapshot next;
    std::set<PartKey> live;
    std::vector<std::pair<PartKey, uint64_t>> kept;
    const int removals = int(rng() % 10), leaving = int(rng() % 5);
    for (int i = 0; i < removals; ++i) {
      const PartKey key{{"gone_" + std::to_string(i), 0}, 0, 0};
      const uint64_t at = 1 + rng() % (version - 1);
      next.removed.emplace_back(key, at);
      if (rng() % 3 == 0)
        live.insert(key);
      else if (version <= kSinceWindow || at > version - kSinceWindow)
        kept.emplace_back(key, at);
    }
    std::vector<PartKey> left;
    for (int i = 0; i < leaving; ++i) left.push_back({{"left_" + std::to_string(i), 1}, i, 0});
    for (const PartKey& key : left) kept.emplace_back(key, version);

    recordRemovals(next, live, left, version);
    EXPECT_EQ(next.removed, kept) << "round " << round;
    EXPECT_EQ(next.removedFloor, version > kSinceWindow ? version - kSinceWindow : 0)
        << "round " << round;
  }
}

}  // namespace
}  // namespace penumbra::server
