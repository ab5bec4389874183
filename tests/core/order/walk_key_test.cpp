// FaceOrder::walkKey: the walk position computed from the tree alone must order
// faces exactly as the (lazily rebuilt) walk does, after builds and after edits.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <string>

#include "core/order/face_order.h"
#include "scenegen/cubes_scene.h"

namespace penumbra {
namespace {

// Every pair of present faces: walkKey order == rank order.
void expectKeysFollowRanks(const FaceOrder& order, const std::string& context) {
  const std::vector<FaceId> faces = order.faceOrder();
  std::vector<FaceOrder::WalkKey> keys;
  for (FaceId f : faces) keys.push_back(order.walkKey(f));
  for (size_t i = 0; i + 1 < faces.size(); ++i)
    ASSERT_LT(keys[i], keys[i + 1]) << context << ": faces at ranks " << i << " and " << i + 1;
}

TEST(WalkKey, OrdersFacesAsTheWalkAfterBuildAndEdits) {
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    CubesSceneOptions options = mixedCubesOptions(seed);
    options.cubes = int(10 + 4 * seed);  // deep enough trees, offending faces sharing cells
    const Scene scene = makeCubesScene(options);
    std::mt19937_64 rng(seed);
    for (size_t light = 0; light < scene.lights().size(); ++light) {
      FaceOrder order(scene, light);
      const std::string where = "seed " + std::to_string(seed) + " light " + std::to_string(light);
      expectKeysFollowRanks(order, where + " build");
      std::set<uint32_t> removed;
      for (int round = 0; round < 4; ++round) {
        const uint32_t object = std::uniform_int_distribution<uint32_t>(0, scene.objects().size() - 1)(rng);
        if (!removed.insert(object).second) continue;
        for (const Face& face : scene.faces())
          if (face.id.object == object) order.removeFace(face.id);
        // Several edits between reads: the walk is rebuilt once, when read.
        expectKeysFollowRanks(order, where + " after removing " + std::to_string(object));
      }
      for (uint32_t object : removed) {
        for (const Face& face : scene.faces())
          if (face.id.object == object) order.insertFace(face);
        expectKeysFollowRanks(order, where + " after adding " + std::to_string(object));
      }
      ASSERT_NO_THROW(order.validate()) << where;
      EXPECT_THROW(order.walkKey(FaceId{99999, 0}), std::out_of_range);
    }
  }
}

}  // namespace
}  // namespace penumbra
