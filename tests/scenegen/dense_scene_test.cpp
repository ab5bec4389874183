// The dense-room generator: seeded, 6N + 6 faces, every box inside the room below
// the light, boxes apart from each other, turned about all three axes, sizes
// shrinking as (15/N)^(1/3).
#include "scenegen/dense_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace penumbra {
namespace {

struct BoxExtent {
  Vec3 min{INFINITY}, max{-INFINITY}, centre{0.0};
  double radius = 0;
};

std::vector<BoxExtent> boxesOf(const Scene& scene) {
  std::vector<BoxExtent> out;
  for (size_t o = 0; o < scene.objects().size(); ++o) {
    if (scene.objects()[o].id.rfind("box_", 0) != 0) continue;
    BoxExtent box;
    std::vector<Vec3> corners;
    for (const Face& face : scene.faces())
      if (face.id.object == scene.handleOf(o))
        for (const Vec3& v : face.polygon) corners.push_back(v);
    for (const Vec3& v : corners) {
      box.min = glm::min(box.min, v);
      box.max = glm::max(box.max, v);
      box.centre += v / double(corners.size());
    }
    for (const Vec3& v : corners) box.radius = std::max(box.radius, glm::length(v - box.centre));
    out.push_back(box);
  }
  return out;
}

TEST(DenseScene, SeededBoxesApartInsideTheRoom) {
  for (int boxes : {15, 150, 600}) {
    SCOPED_TRACE(boxes);
    const Scene a = makeDenseScene({.boxes = boxes, .seed = 7});
    const Scene b = makeDenseScene({.boxes = boxes, .seed = 7});
    ASSERT_EQ(a.faces().size(), size_t(6 * boxes + 6));
    ASSERT_EQ(a.lights().size(), 1u);
    EXPECT_NEAR(a.lights()[0].area(), 1.0, 1e-12);
    for (size_t i = 0; i < a.faces().size(); ++i) EXPECT_EQ(a.faces()[i].polygon, b.faces()[i].polygon);
    const std::vector<BoxExtent> extents = boxesOf(a);
    ASSERT_EQ(extents.size(), size_t(boxes));
    const double scale = std::cbrt(15.0 / boxes);
    double largest = 0;
    for (size_t i = 0; i < extents.size(); ++i) {
      const BoxExtent& e = extents[i];
      EXPECT_GT(e.min.x, -kDenseHalfSide);
      EXPECT_LT(e.max.x, kDenseHalfSide);
      EXPECT_GT(e.min.z, -kDenseHalfSide);
      EXPECT_LT(e.max.z, kDenseHalfSide);
      EXPECT_GT(e.min.y, 0);
      EXPECT_LT(e.max.y, kDenseLightY);
      largest = std::max(largest, e.radius);
      for (size_t j = 0; j < i; ++j)
        EXPECT_GT(glm::length(e.centre - extents[j].centre), e.radius + extents[j].radius);
    }
    EXPECT_LE(largest, std::sqrt(3.0) / 2 * kDenseMaxSide * scale + 1e-12);
  }
  EXPECT_NE(makeDenseScene({.boxes = 15, .seed = 1}).faces()[10].polygon,
            makeDenseScene({.boxes = 15, .seed = 2}).faces()[10].polygon);
}

TEST(DenseScene, BoxesAreTurnedAboutEveryAxis) {
  const Scene scene = makeDenseScene({.boxes = 50, .seed = 3});
  int tilted = 0;  // boxes with no face normal near any axis
  for (size_t o = 6; o < scene.objects().size(); ++o) {
    const Transform& t = scene.objects()[o].transform;
    tilted += std::abs(std::sin(glm::radians(t.rotateDeg.x))) > 0.1 &&
              std::abs(std::sin(glm::radians(t.rotateDeg.z))) > 0.1;
  }
  EXPECT_GT(tilted, 25);
}

}  // namespace
}  // namespace penumbra
