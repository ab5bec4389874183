#include "scenegen/sphere_scene.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "scenegen/dense_scene.h"
#include "scenegen/scene_parts.h"

namespace penumbra {

UvSphereGrid uvSphereGrid(int faces) {
  UvSphereGrid grid;
  grid.stacks = std::max(2, int(std::lround(std::sqrt(std::max(faces, 0) / 2.0))));
  grid.slices = std::max(3, int(std::lround(double(faces) / grid.stacks)));
  return grid;
}

Scene makeSphereScene(const SphereSceneOptions& options) {
  if (options.faces < 6)
    throw std::invalid_argument("makeSphereScene: a sphere needs at least 6 faces");
  const Vec3& c = options.centre;
  const double r = options.radius;
  if (!(r > 0) || std::abs(c.x) + r >= kDenseHalfSide || std::abs(c.z) + r >= kDenseHalfSide ||
      c.y - r <= 0 || c.y + r >= kDenseLightY)
    throw std::invalid_argument(
        "makeSphereScene: the sphere must lie inside the room, below the light");
  std::vector<Light> lights{
      squareCeilingLight("light", Vec3(0, kDenseLightY, 0), kDenseLightSide, 0, Vec3(1, 0, 0))};
  std::vector<Material> materials{{"white", Vec3(0.8)}, {"clay", Vec3(0.75, 0.45, 0.3)}};
  std::vector<Object> objects = roomObjects(kDenseHalfSide, kDenseHalfSide, kDenseHeight);

  Object sphere;
  sphere.id = "sphere";
  sphere.material = "clay";
  const UvSphereGrid grid = uvSphereGrid(options.faces);
  addUvSphere(sphere, c, r, grid.stacks, grid.slices);
  objects.push_back(std::move(sphere));

  Camera camera;
  camera.position = Vec3(0, 1.6, kDenseHalfSide - 0.25);
  camera.target = c;
  camera.fovYDeg = 60;
  camera.far = 8 * kDenseHalfSide;
  return Scene(std::move(lights), std::move(materials), std::move(objects), camera);
}

}  // namespace penumbra
