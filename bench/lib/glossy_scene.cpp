#include "bench/lib/glossy_scene.h"

#include "scenegen/scene_parts.h"

namespace penumbra {

Scene makeGlossyScene(const GlossySceneOptions& options) {
  Light light;
  light.id = "panel";
  // Counter-clockwise seen from below: emits down.
  light.polygon = {{-0.7, 2.5, -0.4}, {0.7, 2.5, -0.4}, {0.7, 2.5, 0.4}, {-0.7, 2.5, 0.4}};
  light.radiance = Vec3(20.0);

  Material floorMaterial{"glossy_floor", Vec3(0.9, 0.6, 0.5)};
  floorMaterial.type = MaterialType::Conductor;
  floorMaterial.roughness = Vec2(options.roughness);
  floorMaterial.eta = Vec3(0.27, 0.68, 1.32);  // copper
  floorMaterial.k = Vec3(3.61, 2.62, 2.29);
  floorMaterial.singleScattering = options.singleScattering;
  const Material white{"white", Vec3(0.8)};

  Object floor = quadObject(
      "floor", {{-2.5, 0, -2.5}, {2.5, 0, -2.5}, {2.5, 0, 2.5}, {-2.5, 0, 2.5}}, Vec3(0, 1, 0));
  floor.material = "glossy_floor";
  Object blocker;
  blocker.id = "blocker";
  blocker.material = "white";
  addBox(blocker, Vec3(-0.35, 1.2, 0.4), Vec3(0.35, 1.5, 1.1));

  Camera camera;
  camera.position = Vec3(0, 1.9, 4.2);
  camera.target = Vec3(0, 0, 0.9);
  camera.fovYDeg = 50;
  camera.far = 20;
  return Scene({light}, {floorMaterial, white}, {floor, blocker}, camera);
}

}  // namespace penumbra
