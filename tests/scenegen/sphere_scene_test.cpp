// The one-sphere generator: stacks × slices faces (1152 → 24 × 48), every sphere vertex at
// the radius from the centre, the sphere closed convex and inside the room below the light;
// a request the room cannot hold is refused.
#include "scenegen/sphere_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace penumbra {
namespace {

TEST(SphereScene, GridFacesRadiusAndClosedConvex) {
  EXPECT_EQ(uvSphereGrid(1152).stacks, 24);
  EXPECT_EQ(uvSphereGrid(1152).slices, 48);
  EXPECT_EQ(uvSphereGrid(300).stacks * uvSphereGrid(300).slices, 300);
  for (int faces : {6, 50, 288, 1152}) {
    const SphereSceneOptions options{.faces = faces};
    const Scene scene = makeSphereScene(options);
    const UvSphereGrid grid = uvSphereGrid(faces);
    const size_t index = *scene.findObject("sphere");
    const Object& sphere = scene.objects()[index];
    EXPECT_EQ(sphere.faces.size(), size_t(grid.stacks * grid.slices)) << faces;
    EXPECT_EQ(scene.faces().size(), sphere.faces.size() + 6) << faces;
    EXPECT_TRUE(scene.isClosedConvex(scene.handleOf(index))) << faces;
    for (const Vec3& v : sphere.vertices)
      EXPECT_NEAR(glm::length(v - options.centre), options.radius, 1e-12) << faces;
    const Plane light = scene.lights()[0].plane();
    for (const Face& face : scene.faces()) {
      if (face.id.object != scene.handleOf(index)) continue;
      for (const Vec3& v : face.polygon) EXPECT_GT(light.signedDistance(v), 0) << faces;
    }
  }
  EXPECT_THROW(makeSphereScene({.faces = 5}), std::invalid_argument);
  EXPECT_THROW(makeSphereScene({.faces = 100, .radius = 2}), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra
