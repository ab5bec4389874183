// The ordering BSP terminates on a face that is off its own plane by more than the
// length tolerance (Scene snaps faces, but FaceOrder must not depend on it): the
// splitting face's own fragments stay on its node, so each node takes a face.
// Was: the fragment split itself again and again, ~200 MB/s until bad_alloc.
#include <gtest/gtest.h>

#include "core/order/face_order.h"
#include "protocol/scene_json.h"

namespace penumbra {
namespace {

TEST(FaceOrderNonPlanar, FaceOffItsPlaneBeyondToleranceIsOrderedInBoundedNodes) {
  const Scene scene = protocol::loadSceneFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cubes15.scene.json");
  // A large tilted quad, one corner 1e-6 of its size off the others' plane: beyond
  // the scene's length tolerance, within the format's planarity tolerance.
  Face face;
  face.id = FaceId{1000, 0};
  face.polygon = {{-2, 0.5, 2}, {2, 0.5, 2}, {2, 0.6, -2}, {-2, 0.6 + 6e-6, -2}};
  face.plane = *planeOf(face.polygon);
  face.area = area(face.polygon);
  ASSERT_GT(std::abs(face.plane.signedDistance(face.polygon[3])), 100 * scene.tolerance().length());

  FaceOrder order(scene, 0, 10'000);  // a runaway throws ResourceLimitError
  const size_t before = order.counters().nodes;
  ASSERT_TRUE(order.insertFace(face));
  EXPECT_LE(order.counters().nodes, before + 200);
  EXPECT_TRUE(order.contains(face.id));
  EXPECT_TRUE(order.removeFace(face.id));
}

}  // namespace
}  // namespace penumbra
