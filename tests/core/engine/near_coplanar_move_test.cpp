// A fuzz finding (tests/fuzz/crashes/edit_frame/near-coplanar-light-edge.json): a cube moved so
// that one face lies 6e-8 m from the plane of the light's edge makes two floor lines cross at a
// shallow angle, and the floor's tree holds a sliver 9e-9 m wide (the length tolerance is 9e-9
// m here) straddling both. DmTree::validate refused it (its centroid was 5e-10 m on the wrong
// side of an ancestor); it is a legitimate cell. The frame must leave a valid engine, equal to a
// rebuild of the moved scene and to the exact reference at every vertex.
#include <gtest/gtest.h>

#include <string>

#include "tests/fuzz/fuzz_support.h"
#include "core/engine/engine.h"
#include "tests/core/engine/incremental_compare.h"
#include "tests/core/engine/reference_check.h"

namespace penumbra {
namespace {

Frame nearCoplanarMove() {
  Edit edit;
  edit.op = Edit::Op::Move;
  edit.id = "box";
  edit.transform.translate = {2.063320727212673, 0.265625, -1.0000000639555767};
  Frame frame;
  frame.edits.push_back(edit);
  return frame;
}

TEST(NearCoplanarMove, FreshBuildOfTheMovedSceneIsValidAndExact) {
  Engine engine(fuzz::tinyScene());
  engine.apply(nearCoplanarMove());
  Engine rebuilt(engine.scene());
  EXPECT_NO_THROW(rebuilt.validate());
  const testing::ReferenceCheck check = testing::checkAgainstReference(rebuilt, "near-coplanar");
  EXPECT_GE(check.vertices, 50u);  // the floor and the two boxes: 100 vertices
  EXPECT_EQ(check.valueErrors, 0u);
  EXPECT_EQ(check.classErrors, 0u);
}

TEST(NearCoplanarMove, FaceNearTheLightEdgePlaneLeavesAValidEngineEqualToARebuild) {
  Engine engine(fuzz::tinyScene());
  engine.apply(nearCoplanarMove());
  EXPECT_NO_THROW(engine.validate());
  Engine rebuilt(engine.scene());
  const testing::EngineDiff diff =
      testing::compareEngines(engine, rebuilt, testing::peakIrradiance(rebuilt), 2000, 7);
  EXPECT_EQ(diff.errors(), 0u) << diff.firstProblem;
}

}  // namespace
}  // namespace penumbra
