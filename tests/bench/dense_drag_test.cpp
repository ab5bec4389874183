// The dense rooms' move-one-box script: one box, small steps, always inside the room and
// clear of every other box (bounding spheres), the box nearest the room's middle first,
// the same script for the same seed.
#include "bench/lib/dense_drag.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "protocol/edits_json.h"
#include "scenegen/dense_scene.h"

namespace penumbra {
namespace {

struct Sphere {
  Vec3 centre{0.0};
  double radius = 0;
};

// Bounding sphere of an object's world corners (centre: their mean, exact for a box).
Sphere sphereOf(const Scene& scene, size_t o) {
  std::vector<Vec3> corners;
  for (const Face& face : scene.faces())
    if (face.id.object == scene.handleOf(o))
      for (const Vec3& v : face.polygon) corners.push_back(v);
  Sphere s;
  for (const Vec3& v : corners) s.centre += v / double(corners.size());
  for (const Vec3& v : corners) s.radius = std::max(s.radius, glm::length(v - s.centre));
  return s;
}

TEST(DenseDrag, OneBoxInSmallStepsClearOfTheRoomAndTheOthers) {
  for (int boxes : {15, 150}) {
    SCOPED_TRACE(boxes);
    Scene scene = makeDenseScene({.boxes = boxes, .seed = 1});
    const EditScript script = denseDragScript(scene, 20, 1);
    ASSERT_EQ(script.frames.size(), 20u);
    EXPECT_EQ(script.name, "drag");
    EXPECT_EQ(script.editedFaces, 6u);
    const std::string id = script.frames[0].edits.at(0).id;
    ASSERT_EQ(id.rfind("box_", 0), 0u);
    const size_t o = *scene.findObject(id);
    const Vec3 start = sphereOf(scene, o).centre;
    Vec3 previous = start;
    for (const Frame& frame : script.frames) {
      ASSERT_EQ(frame.edits.size(), 1u);
      ASSERT_EQ(frame.edits[0].id, id);
      scene.setTransform(scene.handleOf(o), frame.edits[0].transform);
      const Sphere moved = sphereOf(scene, o);
      EXPECT_LE(glm::length(moved.centre - previous), kDenseDragStep + 1e-9);
      EXPECT_NEAR(moved.centre.y, start.y, 1e-9);  // horizontal
      previous = moved.centre;
      for (const Face& face : scene.faces())
        if (face.id.object == scene.handleOf(o))
          for (const Vec3& v : face.polygon) {
            EXPECT_LT(std::abs(v.x), kDenseHalfSide);
            EXPECT_LT(std::abs(v.z), kDenseHalfSide);
            EXPECT_GT(v.y, 0);
            EXPECT_LT(v.y, kDenseLightY);
          }
      for (size_t j = 0; j < scene.objects().size(); ++j)
        if (j != o && scene.objects()[j].id.rfind("box_", 0) == 0) {
          const Sphere other = sphereOf(scene, j);
          EXPECT_GT(glm::length(other.centre - moved.centre), other.radius + moved.radius);
        }
    }
    // The whole path when some candidate has it clear (20 × 2 cm in these rooms).
    EXPECT_NEAR(glm::length(previous - start), 20 * kDenseDragStep, 1e-9);
  }
}

TEST(DenseDrag, SameSeedSameScript) {
  const Scene scene = makeDenseScene({.boxes = 60, .seed = 4});
  EXPECT_EQ(protocol::writeEditScript(denseDragScript(scene, 5, 2).frames),
            protocol::writeEditScript(denseDragScript(scene, 5, 2).frames));
  EXPECT_THROW(denseDragScript(makeDenseScene({.boxes = 0, .seed = 1}), 5, 1),
               std::invalid_argument);
}

}  // namespace
}  // namespace penumbra
