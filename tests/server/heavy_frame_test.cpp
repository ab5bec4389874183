// Which frames take the heavy lane of the edit workers (isHeavyFrame): those whose work grows
// with the whole scene — lights added or reshaped, volumes, large objects — and not drags or a
// light's radiance.
#include <gtest/gtest.h>

#include "server/frame_batch.h"

namespace penumbra::server {
namespace {

Frame frameWith(Edit edit) {
  Frame frame;
  frame.edits.push_back(std::move(edit));
  return frame;
}

TEST(HeavyFrame, LightsVolumesAndLargeObjectsAreHeavyDragsAreNot) {
  Edit move;
  move.op = Edit::Op::Move;
  EXPECT_FALSE(isHeavyFrame(frameWith(move)));
  Edit radiance;
  radiance.op = Edit::Op::SetLight;
  radiance.radiance = Vec3(1, 1, 1);
  EXPECT_FALSE(isHeavyFrame(frameWith(radiance)));
  Edit reshape = radiance;
  reshape.polygon = Polygon3{};
  EXPECT_TRUE(isHeavyFrame(frameWith(reshape)));
  Edit addLight;
  addLight.op = Edit::Op::AddLight;
  EXPECT_TRUE(isHeavyFrame(frameWith(addLight)));
  Edit addVolume;
  addVolume.op = Edit::Op::AddVolume;
  EXPECT_TRUE(isHeavyFrame(frameWith(addVolume)));
  Edit small;
  small.op = Edit::Op::Add;
  small.object.faces.resize(kHeavyObjectFaces);
  EXPECT_FALSE(isHeavyFrame(frameWith(small)));
  Edit large = small;
  large.object.faces.resize(kHeavyObjectFaces + 1);
  EXPECT_TRUE(isHeavyFrame(frameWith(large)));
  // One heavy edit makes the frame heavy.
  Frame mixed = frameWith(move);
  mixed.edits.push_back(addLight);
  EXPECT_TRUE(isHeavyFrame(mixed));
}

}  // namespace
}  // namespace penumbra::server
