#include "bench/lib/dense_drag.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

#include "scenegen/dense_scene.h"

namespace penumbra {

namespace {

constexpr int kDirections = 16;
constexpr size_t kCandidates = 32;

struct BoxSphere {
  size_t object = 0;
  Vec3 centre{0.0};
  double radius = 0;
};

BoxSphere sphereOf(const Scene& scene, size_t o) {
  const Object& object = scene.objects()[o];
  BoxSphere s{o};
  std::vector<Vec3> world;
  for (const Vec3& v : object.vertices) world.push_back(object.transform.apply(v));
  for (const Vec3& p : world) s.centre += p / double(world.size());
  for (const Vec3& p : world) s.radius = std::max(s.radius, glm::length(p - s.centre));
  return s;
}

double segmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp(glm::dot(p - a, ab) / std::max(glm::dot(ab, ab), 1e-300), 0.0, 1.0);
  return glm::length(p - (a + t * ab));
}

// The sphere of box k swept from its centre to `end` stays clear of the room and the rest.
bool clearPath(const std::vector<BoxSphere>& boxes, size_t k, const Vec3& end) {
  const BoxSphere& box = boxes[k];
  const double margin = box.radius + kDenseGap;
  for (const Vec3& p : {box.centre, end})
    if (std::abs(p.x) > kDenseHalfSide - margin || std::abs(p.z) > kDenseHalfSide - margin ||
        p.y < margin || p.y > kDenseLightY - margin)
      return false;
  for (size_t j = 0; j < boxes.size(); ++j)
    if (j != k && segmentDistance(boxes[j].centre, box.centre, end) < margin + boxes[j].radius)
      return false;
  return true;
}

}  // namespace

EditScript denseDragScript(const Scene& scene, int frames, uint64_t seed) {
  std::vector<BoxSphere> boxes;
  for (size_t o : movableObjects(scene)) boxes.push_back(sphereOf(scene, o));
  if (boxes.empty()) throw std::invalid_argument("denseDragScript: the scene has no box");
  const Vec3 middle(0, kDenseHeight / 2, 0);
  std::vector<size_t> order(boxes.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return glm::length(boxes[a].centre - middle) < glm::length(boxes[b].centre - middle);
  });

  const double wanted = kDenseDragStep * std::max(frames, 1);
  size_t best = order.front();
  Vec3 bestDirection(1, 0, 0);
  double bestLength = 0;
  for (size_t c = 0; c < std::min(order.size(), kCandidates) && bestLength < wanted; ++c) {
    const size_t k = order[c];
    for (int d = 0; d < kDirections && bestLength < wanted; ++d) {
      const double angle = 2 * M_PI * double((d + seed) % kDirections) / kDirections;
      const Vec3 direction(std::cos(angle), 0, std::sin(angle));
      double length = wanted;
      for (int halving = 0; halving < 8 && length > bestLength; ++halving, length *= 0.5)
        if (clearPath(boxes, k, boxes[k].centre + length * direction)) {
          best = k, bestDirection = direction, bestLength = length;
          break;
        }
    }
  }

  EditScript script;
  script.name = "drag";
  const Object& box = scene.objects()[boxes[best].object];
  for (int f = 1; f <= frames; ++f) {
    Edit edit;
    edit.op = Edit::Op::Move;
    edit.id = box.id;
    edit.transform = box.transform;
    edit.transform.translate += (bestLength * f / frames) * bestDirection;
    edit.transform.rotateDeg.y += kDenseDragTurnDeg * f;
    Frame frame;
    frame.edits.push_back(std::move(edit));
    script.frames.push_back(std::move(frame));
  }
  size_t faces = 0;
  for (const Object& object : scene.objects()) faces += object.faces.size();
  script.editedFaces = box.faces.size();
  script.faceShare = double(script.editedFaces) / double(faces);
  char subject[160];
  const Vec3 c = boxes[best].centre;
  std::snprintf(subject, sizeof subject,
                "%s: bounding radius %.3g m, %.3g m above the floor, %.3g m off the light's axis, "
                "moved %.3g m",
                box.id.c_str(), boxes[best].radius, c.y, std::hypot(c.x, c.z), bestLength);
  script.subject = subject;
  return script;
}

}  // namespace penumbra
