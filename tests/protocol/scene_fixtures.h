// Test fixtures for the protocol tests: a valid base scene as JSON, a unit cube,
// and exact comparisons of scenes. Plain functions; thread-safe.
#pragma once

#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/scene/scene.h"

namespace penumbra::protocol::testing {

// Unit cube centred on the origin; faces CCW seen from outside.
inline nlohmann::json cubeVertices() {
  return nlohmann::json::parse(R"([[-0.5,-0.5,-0.5],[0.5,-0.5,-0.5],[0.5,0.5,-0.5],[-0.5,0.5,-0.5],
                                   [-0.5,-0.5,0.5],[0.5,-0.5,0.5],[0.5,0.5,0.5],[-0.5,0.5,0.5]])");
}
inline nlohmann::json cubeFaces() {
  return nlohmann::json::parse(R"([[0,3,2,1],[4,5,6,7],[0,4,7,3],[1,2,6,5],[0,1,5,4],[3,7,6,2]])");
}

// lights[0] "lamp"; materials white, red; objects[0] floor (static),
// objects[1] box1 (red, transformed cube), objects[2] box2 (cube); a camera.
inline nlohmann::json baseSceneJson() {
  nlohmann::json scene = nlohmann::json::parse(R"({
    "format": "penumbra.scene",
    "version": 1,
    "lights": [
      { "id": "lamp",
        "polygon": [[-0.5, 2.99, -0.5], [0.5, 2.99, -0.5], [0.5, 2.99, 0.5], [-0.5, 2.99, 0.5]],
        "radiance": [10.0, 10.0, 10.0] }
    ],
    "materials": {
      "white": { "albedo": [0.8, 0.8, 0.8] },
      "red":   { "albedo": [0.7, 0.1, 0.1] }
    },
    "objects": [
      { "id": "floor",
        "vertices": [[-3, 0, -3], [-3, 0, 3], [3, 0, 3], [3, 0, -3]],
        "faces": [[0, 1, 2, 3]],
        "material": "white",
        "static": true },
      { "id": "box1", "material": "red",
        "transform": { "translate": [0, 0.5, 0], "rotate_deg": [0, 30, 0], "scale": [1, 1, 1] } },
      { "id": "box2", "transform": { "translate": [1.5, 0.5, 0] } }
    ],
    "camera": { "position": [0, 1.5, 6], "target": [0, 1, 0], "up": [0, 1, 0],
                "projection": "perspective", "fov_y_deg": 45, "near": 0.1, "far": 100 }
  })");
  for (int i : {1, 2}) {
    scene["objects"][i]["vertices"] = cubeVertices();
    scene["objects"][i]["faces"] = cubeFaces();
  }
  return scene;
}

// Field-by-field exact equality (materials compared by id: JSON orders them by name).
inline void expectSameScene(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.lights().size(), b.lights().size());
  for (size_t i = 0; i < a.lights().size(); ++i) {
    EXPECT_EQ(a.lights()[i].id, b.lights()[i].id);
    EXPECT_EQ(a.lights()[i].polygon, b.lights()[i].polygon) << "light " << i;
    EXPECT_EQ(a.lights()[i].radiance, b.lights()[i].radiance) << "light " << i;
  }
  ASSERT_EQ(a.materials().size(), b.materials().size());
  for (const Material& m : a.materials()) {
    const auto j = b.findMaterial(m.id);
    ASSERT_TRUE(j.has_value()) << m.id;
    EXPECT_EQ(m.albedo, b.materials()[*j].albedo) << m.id;
    EXPECT_TRUE(m == b.materials()[*j]) << m.id << ": microfacet keys differ";
  }
  ASSERT_EQ(a.objects().size(), b.objects().size());
  for (size_t i = 0; i < a.objects().size(); ++i) {
    const Object &x = a.objects()[i], &y = b.objects()[i];
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.vertices, y.vertices) << x.id;
    EXPECT_EQ(x.faces, y.faces) << x.id;
    EXPECT_EQ(x.material, y.material) << x.id;
    EXPECT_EQ(x.isStatic, y.isStatic) << x.id;
    EXPECT_EQ(x.transform, y.transform) << x.id;
  }
  ASSERT_EQ(a.camera().has_value(), b.camera().has_value());
  if (a.camera()) {
    const Camera &x = *a.camera(), &y = *b.camera();
    EXPECT_EQ(x.position, y.position);
    EXPECT_EQ(x.target, y.target);
    EXPECT_EQ(x.up, y.up);
    EXPECT_EQ(x.projection, y.projection);
    EXPECT_EQ(x.fovYDeg, y.fovYDeg);
    EXPECT_EQ(x.height, y.height);
    EXPECT_EQ(x.near, y.near);
    EXPECT_EQ(x.far, y.far);
  }
  ASSERT_EQ(a.faces().size(), b.faces().size());
  for (size_t i = 0; i < a.faces().size(); ++i) EXPECT_EQ(a.faces()[i].polygon, b.faces()[i].polygon);
}

}  // namespace penumbra::protocol::testing
