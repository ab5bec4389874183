#include "scenegen/dense_scene.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "scenegen/scene_parts.h"

namespace penumbra {

namespace {

constexpr int kDensePlacementTries = 100000;

struct Sphere {
  Vec3 centre{0.0};
  double radius = 0;
};

// A free spot for a sphere of `radius`: kDenseGap clear of the room, the light's
// plane and every placed sphere (rejection sampling; the fill stays ~10%).
Vec3 placeSphere(std::mt19937_64& rng, double radius, const std::vector<Sphere>& placed) {
  const double margin = radius + kDenseGap;
  const double range = kDenseHalfSide - margin, low = margin, high = kDenseLightY - margin;
  if (range <= 0 || high <= low) throw std::invalid_argument("makeDenseScene: box larger than the room");
  for (int attempt = 0; attempt < kDensePlacementTries; ++attempt) {
    const Vec3 c(uniform(rng, -range, range), uniform(rng, low, high), uniform(rng, -range, range));
    bool clear = true;
    for (const Sphere& s : placed)
      if (glm::length(c - s.centre) < radius + s.radius + kDenseGap) {
        clear = false;
        break;
      }
    if (clear) return c;
  }
  throw std::runtime_error("makeDenseScene: could not place a box (room too crowded)");
}

}  // namespace

Scene makeDenseScene(const DenseSceneOptions& options) {
  if (options.boxes < 0) throw std::invalid_argument("makeDenseScene: negative box count");
  std::mt19937_64 rng(options.seed);
  std::vector<Light> lights{squareCeilingLight("light", Vec3(0, kDenseLightY, 0), kDenseLightSide, 0,
                                               Vec3(1, 0, 0))};
  std::vector<Material> materials{{"white", Vec3(0.8)}, {"clay", Vec3(0.75, 0.45, 0.3)}};
  std::vector<Object> objects = roomObjects(kDenseHalfSide, kDenseHalfSide, kDenseHeight);

  // Same share of the room filled at every count: side ∝ (15 / N)^(1/3).
  const double scale = options.boxes > 0 ? std::cbrt(15.0 / options.boxes) : 1.0;
  std::vector<Sphere> placed;
  for (int i = 0; i < options.boxes; ++i) {
    const Vec3 size(uniform(rng, kDenseMinSide, kDenseMaxSide) * scale,
                    uniform(rng, kDenseMinSide, kDenseMaxSide) * scale,
                    uniform(rng, kDenseMinSide, kDenseMaxSide) * scale);
    const Vec3 angles(uniform(rng, 0, 360), uniform(rng, 0, 360), uniform(rng, 0, 360));
    const double radius = glm::length(size) / 2;
    const Vec3 centre = placeSphere(rng, radius, placed);
    placed.push_back({centre, radius});

    Object box;
    box.id = "box_" + std::to_string(i);
    box.material = (i % 2) ? "clay" : "white";
    addBox(box, Vec3(-0.5), Vec3(0.5));
    box.transform.translate = centre;
    box.transform.rotateDeg = angles;
    box.transform.scale = size;
    objects.push_back(std::move(box));
  }

  Camera camera;
  camera.position = Vec3(0, 1.6, kDenseHalfSide - 0.25);
  camera.target = Vec3(0, 1.2, 0);
  camera.fovYDeg = 60;
  camera.far = 8 * kDenseHalfSide;
  return Scene(std::move(lights), std::move(materials), std::move(objects), camera);
}

}  // namespace penumbra
