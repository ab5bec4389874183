#include "bench/lib/edit_scripts.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <stdexcept>

#include "core/geom/polygon.h"
#include "scenegen/cubes_scene.h"

namespace penumbra {

namespace {

constexpr double kDragStep = 0.08;    // metres per frame at most: a small move
constexpr double kDragTurnDeg = 0.5;  // the dragged cube turns a little per frame
// Horizontal distance from the first light's centre to the dragged cube's centre:
// a cube near the light's edge (side 1.5 m in makeCubesScene), well inside the
// smallest room (5 m), so the same situation exists at every scene size.
constexpr double kDragLightDistance = 1.5;
constexpr double kWiggleRadius = 0.025;  // share moves stay inside the generator's 1/16 m gaps
constexpr int kWiggleSteps = 12;         // frames per circle

bool isRoom(const Object& object) {
  return object.id == "floor" || object.id == "ceiling" || object.id.rfind("wall_", 0) == 0;
}

// An object's world bounding box and the smallest disc about the box's centre
// holding its footprint (tighter than the box's half-diagonal for a turned cube).
struct WorldBox {
  Vec3 min{0.0}, max{0.0};
  double radius = 0;
  double footprintRadius() const { return radius; }
  Vec2 footprintCentre() const { return {0.5 * (min.x + max.x), 0.5 * (min.z + max.z)}; }
};

WorldBox worldBox(const Object& object) {
  WorldBox box{Vec3(INFINITY), Vec3(-INFINITY)};
  std::vector<Vec3> world;
  for (const Vec3& v : object.vertices) {
    world.push_back(object.transform.apply(v));
    box.min = glm::min(box.min, world.back());
    box.max = glm::max(box.max, world.back());
  }
  for (const Vec3& p : world)
    box.radius = std::max(box.radius, glm::length(Vec2{p.x, p.z} - box.footprintCentre()));
  return box;
}

size_t faceCount(const Scene& scene) {
  size_t faces = 0;
  for (const Object& object : scene.objects()) faces += object.faces.size();
  return faces;
}

Frame moveFrame(const std::vector<const Object*>& objects, const Vec3& offset, double turnDeg) {
  Frame frame;
  for (const Object* object : objects) {
    Edit edit;
    edit.op = Edit::Op::Move;
    edit.id = object->id;
    edit.transform = object->transform;
    edit.transform.translate += offset;
    edit.transform.rotateDeg.y += turnDeg;
    frame.edits.push_back(std::move(edit));
  }
  return frame;
}

// Distance from point p to segment a→b.
double segmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double t = std::clamp(glm::dot(p - a, ab) / std::max(glm::dot(ab, ab), 1e-300), 0.0, 1.0);
  return glm::length(p - (a + t * ab));
}

}  // namespace

std::vector<size_t> movableObjects(const Scene& scene) {
  std::vector<size_t> out;
  for (size_t i = 0; i < scene.objects().size(); ++i)
    if (!isRoom(scene.objects()[i]) && !scene.objects()[i].isStatic) out.push_back(i);
  return out;
}

EditScript dragScript(const Scene& scene, int frames, uint64_t seed) {
  const std::vector<size_t> movable = movableObjects(scene);
  if (movable.empty()) throw std::invalid_argument("dragScript: the scene has no movable object");
  std::vector<WorldBox> boxes;
  for (size_t i : movable) boxes.push_back(worldBox(scene.objects()[i]));

  // The first light's centre on the floor (the room's centre without a light).
  const Bounds room = scene.bounds();
  const Vec3 lightCentre =
      scene.lights().empty() ? 0.5 * (room.min + room.max) : centroid(scene.lights()[0].polygon);
  const Vec2 lightOnFloor{lightCentre.x, lightCentre.z};
  auto lightDistance = [&](size_t k) {
    return glm::length(boxes[k].footprintCentre() - lightOnFloor);
  };

  // Free cubes standing on the floor (nothing rests on them) first, closest to
  // kDragLightDistance first: the same situation whatever the room's size.
  const double eps = 1e-9 * room.diagonal();
  auto isFree = [&](size_t k) {
    for (size_t j = 0; j < boxes.size(); ++j) {
      if (j == k || std::abs(boxes[j].min.y - boxes[k].max.y) > eps) continue;
      const double d = glm::length(boxes[j].footprintCentre() - boxes[k].footprintCentre());
      if (d < boxes[j].footprintRadius() + boxes[k].footprintRadius()) return false;
    }
    return true;
  };
  std::vector<size_t> candidates(movable.size());
  std::iota(candidates.begin(), candidates.end(), 0);
  std::stable_sort(candidates.begin(), candidates.end(), [&](size_t a, size_t b) {
    return std::abs(lightDistance(a) - kDragLightDistance) <
           std::abs(lightDistance(b) - kDragLightDistance);
  });
  std::stable_partition(candidates.begin(), candidates.end(), [&](size_t k) {
    return isFree(k) && std::abs(boxes[k].min.y) <= eps &&
           scene.objects()[movable[k]].id.rfind("cube_", 0) == 0;
  });
  // A generated scene's subject cube is literally the same cube at every size.
  for (size_t k = 0; k < movable.size(); ++k)
    if (scene.objects()[movable[k]].id == kSubjectCubeId) candidates = {k};

  // Sixteen directions relative to the light, the closest to round it first (the
  // light distance stays about the same); the seed's parity picks which way round.
  const double turn = seed % 2 ? -1.0 : 1.0;
  const double kRelativeDeg[16] = {90,  -90,  67.5, -67.5, 112.5, -112.5, 45, -45,
                                   135, -135, 22.5, -22.5, 157.5, -157.5, 0,  180};

  // Among the first candidates, the first with a clear path of the wanted length
  // (else the longest clear path, halving the length): the swept footprint stays
  // in the room and off every other footprint.
  const double wanted = kDragStep * frames;
  size_t best = candidates.front();
  Vec2 bestDirection{1, 0};
  double bestLength = 0;
  for (size_t c = 0; c < std::min<size_t>(candidates.size(), 16); ++c) {
    const size_t k = candidates[c];
    const Vec2 start = boxes[k].footprintCentre();
    const double radius = boxes[k].footprintRadius();
    const Vec2 outwards = start - lightOnFloor;
    const double radial = glm::length(outwards) > eps ? std::atan2(outwards.y, outwards.x) : 0.0;
    for (double relativeDeg : kRelativeDeg) {
      const double angle = radial + turn * glm::radians(relativeDeg);
      const Vec2 direction{std::cos(angle), std::sin(angle)};
      double length = wanted;
      for (int halving = 0; halving < 8 && length > bestLength; ++halving, length *= 0.5) {
        const Vec2 end = start + length * direction;
        bool clear = end.x - radius > room.min.x + 0.05 && end.x + radius < room.max.x - 0.05 &&
                     end.y - radius > room.min.z + 0.05 && end.y + radius < room.max.z - 0.05;
        for (size_t j = 0; clear && j < boxes.size(); ++j)
          if (j != k && segmentDistance(boxes[j].footprintCentre(), start, end) <
                            radius + boxes[j].footprintRadius() + 0.01)
            clear = false;
        if (clear) {
          best = k;
          bestDirection = direction;
          bestLength = length;
          break;
        }
      }
      if (bestLength >= wanted) break;
    }
    if (bestLength >= wanted) break;
  }

  EditScript script;
  script.name = "drag";
  const Object& cube = scene.objects()[movable[best]];
  for (int f = 1; f <= frames; ++f) {
    const double t = bestLength * f / frames;
    const Vec3 offset{t * bestDirection.x, 0, t * bestDirection.y};
    script.frames.push_back(moveFrame({&cube}, offset, kDragTurnDeg * f));
  }
  script.editedFaces = cube.faces.size();
  script.faceShare = double(script.editedFaces) / double(faceCount(scene));
  char subject[160];
  std::snprintf(
      subject, sizeof subject, "%s: %.3g m cube, %.3g m from the light on the floor, moved %.3g m",
      cube.id.c_str(), boxes[best].max.y - boxes[best].min.y, lightDistance(best), bestLength);
  script.subject = subject;
  return script;
}

EditScript moveShareScript(const Scene& scene, double share, int frames, uint64_t seed) {
  std::vector<size_t> movable = movableObjects(scene);
  if (movable.empty())
    throw std::invalid_argument("moveShareScript: the scene has no movable object");
  std::mt19937_64 rng(seed);
  std::shuffle(movable.begin(), movable.end(), rng);
  const double target = share * double(faceCount(scene));
  std::vector<const Object*> chosen;
  size_t faces = 0;
  for (size_t i : movable) {
    const size_t f = scene.objects()[i].faces.size();
    // Take the object if it brings the total closer to the target (always the first).
    if (!chosen.empty() && std::abs(double(faces + f) - target) >= std::abs(double(faces) - target))
      continue;
    chosen.push_back(&scene.objects()[i]);
    faces += f;
  }
  // Keep the scene's order: frames then list edits as the objects appear.
  std::sort(chosen.begin(), chosen.end());

  EditScript script;
  script.name = "move-" + std::to_string(int(std::lround(share * 100))) + "pct";
  for (int f = 1; f <= frames; ++f) {
    const double angle = 2 * M_PI * f / kWiggleSteps;
    const Vec3 offset{kWiggleRadius * (std::cos(angle) - 1), 0, kWiggleRadius * std::sin(angle)};
    script.frames.push_back(moveFrame(chosen, offset, 0));
  }
  script.editedFaces = faces;
  script.faceShare = double(faces) / double(faceCount(scene));
  return script;
}

EditScript removeAddScript(const Scene& scene, int pairs, uint64_t seed) {
  std::vector<size_t> movable = movableObjects(scene);
  if (movable.empty())
    throw std::invalid_argument("removeAddScript: the scene has no movable object");
  std::mt19937_64 rng(seed);
  std::shuffle(movable.begin(), movable.end(), rng);
  EditScript script;
  script.name = "remove-add";
  for (int p = 0; p < pairs; ++p) {
    const Object& object = scene.objects()[movable[size_t(p) % movable.size()]];
    Edit remove;
    remove.op = Edit::Op::Remove;
    remove.id = object.id;
    script.frames.push_back(Frame{{remove}});
    Edit add;
    add.op = Edit::Op::Add;
    add.id = object.id;
    add.object = object;
    script.frames.push_back(Frame{{add}});
    script.editedFaces = std::max(script.editedFaces, object.faces.size());
  }
  script.faceShare = double(script.editedFaces) / double(faceCount(scene));
  return script;
}

EditScript buildUpScript(const Scene& scene, int maxObjects) {
  const std::vector<size_t> movable = movableObjects(scene);
  EditScript script;
  script.name = "build-up";
  Frame empty;
  for (size_t i : movable) {
    Edit remove;
    remove.op = Edit::Op::Remove;
    remove.id = scene.objects()[i].id;
    empty.edits.push_back(std::move(remove));
  }
  script.frames.push_back(std::move(empty));
  const size_t count =
      maxObjects > 0 ? std::min(movable.size(), size_t(maxObjects)) : movable.size();
  for (size_t k = 0; k < count; ++k) {
    const Object& object = scene.objects()[movable[k]];
    Edit add;
    add.op = Edit::Op::Add;
    add.id = object.id;
    add.object = object;
    script.frames.push_back(Frame{{add}});
    script.editedFaces = std::max(script.editedFaces, object.faces.size());
  }
  script.faceShare = double(script.editedFaces) / double(faceCount(scene));
  return script;
}

std::vector<EditScript> standardEditScripts(const Scene& scene, uint64_t seed) {
  std::vector<EditScript> scripts;
  scripts.push_back(dragScript(scene, 100, seed));
  for (double share : {0.01, 0.05, 0.10, 0.30})
    scripts.push_back(moveShareScript(scene, share, 10, seed));
  scripts.push_back(removeAddScript(scene, 5, seed));
  scripts.push_back(buildUpScript(scene, 0));
  return scripts;
}

}  // namespace penumbra
