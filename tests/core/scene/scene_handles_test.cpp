// Scene::setHandles (core/scene/scene.h): a scene read back from JSON (numbered 0..n-1) takes the
// handles of the scene it copies — faces, objects and shapes are found by them, the next added
// object gets the next handle — and bad handles are refused, changing nothing.
#include <gtest/gtest.h>

#include <stdexcept>

#include "core/scene/scene.h"
#include "scenegen/scene_parts.h"

namespace penumbra {
namespace {

Object box(const std::string& id, double x) {
  Object object;
  object.id = id;
  addBox(object, Vec3(x, 0, 0), Vec3(x + 1, 1, 1));
  return object;
}

Scene threeBoxes() {
  Light light{"light", {{-0.5, 6, -0.5}, {-0.5, 6, 0.5}, {0.5, 6, 0.5}, {0.5, 6, -0.5}}, Vec3(10)};
  return Scene({light}, {}, {box("a", -4), box("b", 0), box("c", 4)});
}

TEST(SceneHandles, ACopyTakesTheHandlesOfTheSceneItCopies) {
  Scene edited = threeBoxes();
  edited.removeObject(0);
  const uint32_t added = edited.addObject(box("d", 8));  // handles now 1, 2, 3; next 4
  ASSERT_EQ(added, 3u);

  Light light{"light", {{-0.5, 6, -0.5}, {-0.5, 6, 0.5}, {0.5, 6, 0.5}, {0.5, 6, -0.5}}, Vec3(10)};
  Scene copy({light}, {}, {box("b", 0), box("c", 4), box("d", 8)});  // as JSON reads it: 0, 1, 2
  copy.setHandles({1, 2, 3}, 4);
  ASSERT_EQ(copy.faces().size(), edited.faces().size());
  for (size_t f = 0; f < copy.faces().size(); ++f)
    EXPECT_EQ(copy.faces()[f].id, edited.faces()[f].id);
  EXPECT_EQ(copy.object(3).id, "d");
  EXPECT_TRUE(copy.isClosedConvex(3));
  EXPECT_FALSE(copy.indexOfHandle(0).has_value());
  EXPECT_EQ(copy.nextHandle(), 4u);
  EXPECT_EQ(copy.addObject(box("e", 12)), 4u);
}

TEST(SceneHandles, BadHandlesAreRefusedAndChangeNothing) {
  Scene scene = threeBoxes();
  EXPECT_THROW(scene.setHandles({0, 1}, 3), std::invalid_argument);     // one short
  EXPECT_THROW(scene.setHandles({0, 2, 2}, 3), std::invalid_argument);  // not increasing
  EXPECT_THROW(scene.setHandles({0, 1, 5}, 5), std::invalid_argument);  // not below the next
  EXPECT_EQ(scene.handleOf(2), 2u);
  EXPECT_EQ(scene.nextHandle(), 3u);
  EXPECT_EQ(scene.faces().back().id.object, 2u);
}

}  // namespace
}  // namespace penumbra
