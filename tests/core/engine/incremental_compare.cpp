#include "tests/core/engine/incremental_compare.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "bench/lib/sample_points.h"
#include "core/illum/face_lookup.h"
#include "core/illum/vertex_illumination.h"
#include "core/reference/exact_irradiance.h"

namespace penumbra::testing {
namespace {

bool close(const Vec3& x, const Vec3& y, double peak) {
  for (int c = 0; c < 3; ++c)
    if (std::abs(x[c] - y[c]) > 1e-9 * std::max(std::abs(x[c]), std::abs(y[c])) + 1e-12 * peak) return false;
  return true;
}

std::string describe(FaceId face) {
  return std::to_string(face.object) + "/" + std::to_string(face.face);
}

// The vertices of one receiver's tree, bucketed for "which vertex is at this point".
class VertexIndex {
 public:
  VertexIndex(const DmTree& tree, double eps) : tree_(tree), eps_(eps) {
    for (VertexId v : tree.vertices()) buckets_[key(tree.position(v))].push_back(v);
  }
  std::optional<VertexId> at(const Vec2& p) const {
    const auto [x, y] = key(p);
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy) {
        const auto it = buckets_.find({x + dx, y + dy});
        if (it == buckets_.end()) continue;
        for (VertexId v : it->second)
          if (glm::length(tree_.position(v) - p) <= eps_) return v;
      }
    return std::nullopt;
  }

 private:
  std::pair<long, long> key(const Vec2& p) const {
    return {long(std::floor(p.x / (2 * eps_))), long(std::floor(p.y / (2 * eps_)))};
  }
  const DmTree& tree_;
  double eps_;
  std::map<std::pair<long, long>, std::vector<VertexId>> buckets_;
};

// The value an engine gives a point of a receiver, lit at exactly that point: from the
// lists around its vertex there if it has one (positions computed in another order
// differ by rounding, and the value can be steep: compare at one point), else from
// the list of the cell holding it.
VertexIrradiance valueAt(const Engine& engine, const Engine::Receiver& r, const VertexIndex& index,
                         const Vec2& q, bool* matched, double* offset) {
  std::vector<const OccluderList*> lists;
  if (const auto v = index.at(q)) {
    *matched = true;
    *offset = glm::length(r.tree.position(*v) - q);
    if (r.tree.position(*v) == q) return engine.value(r, *v);  // lit at this very point
    for (CellId c : r.tree.cellsAround(*v)) lists.push_back(&r.tree.occluders(c));
  } else {
    *matched = false;
    lists.push_back(&r.tree.occluders(r.tree.locate(q)));
  }
  return illuminatePoint(engine.scene(), r.frame.to3D(q), r.frame.normal,
                         shadingNormalAt(engine.scene(), r.face, r.frame.normal, r.frame.to3D(q)), lists);
}

double distanceToBoundary(const Polygon2& polygon, const Vec2& q) {
  double best = INFINITY;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
    const Vec2 ab = b - a;
    const double t = std::clamp(glm::dot(q - a, ab) / std::max(glm::dot(ab, ab), 1e-300), 0.0, 1.0);
    best = std::min(best, glm::length(q - (a + t * ab)));
  }
  return best;
}

// Every discontinuity segment `from` keeps for its inserted occluders, sampled, must lie
// on an edge of `to` or inside an umbra of its light there (culled: DmTree::insert).
void compareSegments(const Engine::Receiver& from, const Engine::Receiver& to, double eps, const char* direction,
                     EngineDiff& diff) {
  from.tree.forEachKeptSegment([&](uint32_t light, FaceId occluder, const KeptSegment& seg) {
    if (glm::length(seg.b - seg.a) <= 4 * eps) return;
    for (double t : {0.15, 0.5, 0.85}) {
      const Vec2 q = seg.a + t * (seg.b - seg.a);
      ++diff.segmentSamples;
      const CellId there = to.tree.locate(q);
      const double d = distanceToBoundary(to.tree.cellPolygon(there), q);
      // Umbra culling: where `to` holds the segment's light wholly hidden, the light adds
      // nothing on either side of the segment, so it bounds no change there.
      if (d > 4 * eps && !hasUmbraEntry(to.tree.occluders(there), light)) {
        if (diff.segmentErrors++ == 0 && diff.firstProblem.empty()) {
          std::ostringstream out;
          out << direction << ": receiver " << describe(from.face) << " segment of occluder "
              << describe(occluder) << " light " << light << " kind " << int(seg.kind)
              << " not on an edge (distance " << d << ")";
          diff.firstProblem = out.str();
        }
        break;
      }
    }
  });
}

}  // namespace

double peakIrradiance(const Engine& engine) {
  double peak = 0;
  for (const auto& r : engine.receivers())
    for (VertexId v : r.tree.vertices()) peak = std::max(peak, engine.value(r, v).irradiance.x);
  return peak;
}

MoveCheck moveAndCompareWithRebuild(Engine& engine, const std::string& id, const Transform& transform,
                                    uint64_t seed) {
  Edit move;
  move.op = Edit::Op::Move;
  move.id = id;
  move.transform = transform;
  MoveCheck check;
  check.frame = engine.apply(Frame{{move}});
  engine.validate();
  const Engine rebuilt(engine.scene());
  check.diff = compareEngines(engine, rebuilt, peakIrradiance(rebuilt), 200, seed);
  return check;
}

EngineDiff compareEngines(const Engine& a, const Engine& b, double peak, size_t randomPoints, uint64_t seed) {
  EngineDiff diff;
  const ExactReference reference(a.scene());
  const double eps = a.scene().tolerance().length();
  auto note = [&](const std::string& problem) {
    if (diff.firstProblem.empty()) diff.firstProblem = problem;
  };
  for (const auto* pair : {&a, &b}) {
    const Engine& one = *pair;
    const Engine& other = pair == &a ? b : a;
    const char* direction = pair == &a ? "incremental->rebuild" : "rebuild->incremental";
    for (const Engine::Receiver& r : one.receivers()) {
      const Engine::Receiver* o = other.receiver(r.face);
      if (!o) {
        ++diff.receiverErrors;
        note(std::string(direction) + ": receiver " + describe(r.face) + " missing");
        continue;
      }
      // (a) vertex values at the same points.
      const VertexIndex index(o->tree, eps);
      for (VertexId v : r.tree.vertices()) {
        ++diff.vertices;
        bool matched = false;
        double offset = 0;
        const VertexIrradiance theirs = valueAt(other, *o, index, r.tree.position(v), &matched, &offset);
        diff.matchedVertices += matched;
        const VertexIrradiance ours = one.value(r, v);
        if (!close(ours.irradiance, theirs.irradiance, peak)) {
          // The exact reference decides which side is off: only `a` being off (or
          // both) is an error of the engine under test.
          const Vec3 at = r.frame.to3D(r.tree.position(v));
          const Vec3 truth =
              reference.evaluate(at, r.frame.normal, shadingNormalAt(one.scene(), r.face, r.frame.normal, at)).irradiance;
          const VertexIrradiance& aValue = pair == &a ? ours : theirs;
          const VertexIrradiance& bValue = pair == &a ? theirs : ours;
          if (close(aValue.irradiance, truth, peak) && !close(bValue.irradiance, truth, peak)) {
            ++diff.secondOffReference;
            continue;
          }
          if (diff.valueErrors++ == 0) {
            std::ostringstream out;
            out.precision(17);
            out << direction << ": receiver " << describe(r.face) << " vertex " << v.index << " ("
                << (matched ? "at a vertex " : "in a cell ") << offset << " away): " << ours.irradiance.x << " vs " << theirs.irradiance.x << " (lists of " << r.tree.cellsAround(v).size()
                << " cells, eps " << eps << ")";
            note(out.str());
          }
        }
      }
      // (c) discontinuity segments up to splitting.
      compareSegments(r, *o, eps, direction, diff);
    }
  }
  // (b) the class (and value) at random points, each lit from its engine's cell.
  for (const SurfacePoint& point : sampleReceivingPoints(a.scene(), randomPoints, seed)) {
    const Engine::Receiver* ra = a.receiver(point.face);
    const Engine::Receiver* rb = b.receiver(point.face);
    if (!ra || !rb) continue;
    ++diff.pointsCompared;
    const VertexIrradiance va = illuminatePoint(a.scene(), point.position, ra->frame.normal,
                                                shadingNormalAt(a.scene(), ra->face, ra->frame.normal, point.position),
                                                {&ra->tree.occluders(ra->tree.locate(ra->frame.to2D(point.position)))});
    const VertexIrradiance vb = illuminatePoint(b.scene(), point.position, rb->frame.normal,
                                                shadingNormalAt(b.scene(), rb->face, rb->frame.normal, point.position),
                                                {&rb->tree.occluders(rb->tree.locate(rb->frame.to2D(point.position)))});
    if (va.lightClass != vb.lightClass || !close(va.irradiance, vb.irradiance, peak)) {
      if (diff.classErrors++ == 0)
        note("random point on " + describe(point.face) + ": class " + toString(va.lightClass) + " vs " +
             toString(vb.lightClass) + ", value " + std::to_string(va.irradiance.x) + " vs " +
             std::to_string(vb.irradiance.x));
    }
  }
  return diff;
}

namespace {

constexpr double kUnit = 1.0 / 64;

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

bool isMovable(const Object& object) {
  return object.id.rfind("cube_", 0) == 0 || object.id.rfind("table_", 0) == 0 || object.id.rfind("new_", 0) == 0;
}
bool isCube(const Object& object) { return object.id.rfind("table_", 0) != 0; }

// The room's half side: the floor's extent.
double roomHalf(const Scene& scene) {
  double half = 0;
  for (const Vec3& v : scene.object(scene.handleOf(*scene.findObject("floor"))).vertices)
    half = std::max(half, std::abs(v.x));
  return half;
}

Object unitCube(const std::string& id) {
  Object object;
  object.id = id;
  object.material = "clay";
  for (int i = 0; i < 8; ++i)
    object.vertices.push_back(Vec3((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 0.5 : -0.5));
  // Outward, counter-clockwise from outside.
  object.faces = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  return object;
}

// A placement for a cube of side `size`: on the floor at a random spot, resting on a
// random cube's top, or beside a cube touching or piercing it.
Transform placeCube(const Scene& scene, std::mt19937_64& rng, double size, const std::string& self) {
  const double half = roomHalf(scene);
  const double range = half - size - 0.05;
  Transform t;
  t.scale = Vec3(size);
  t.rotateDeg = Vec3(0, uniform(rng, 0, 90), 0);
  t.translate = Vec3(uniform(rng, -range, range), size / 2, uniform(rng, -range, range));
  std::vector<const Object*> cubes;
  for (const Object& o : scene.objects())
    if (isMovable(o) && isCube(o) && o.id != self) cubes.push_back(&o);
  if (cubes.empty()) return t;
  const Object& other = *cubes[std::uniform_int_distribution<size_t>(0, cubes.size() - 1)(rng)];
  const Transform& ot = other.transform;
  const double otherSize = ot.scale.x;
  const double top = ot.translate.y + otherSize / 2;
  const int mode = std::uniform_int_distribution<int>(0, 3)(rng);
  if (mode == 1 && top + size <= 2.0) {  // resting on its top
    t.translate = Vec3(ot.translate.x + uniform(rng, -0.2, 0.2) * otherSize, top + size / 2,
                       ot.translate.z + uniform(rng, -0.2, 0.2) * otherSize);
  } else if (mode == 2) {  // beside it, same rotation: faces touching (coplanar contact)
    t.rotateDeg = ot.rotateDeg;
    const double a = glm::radians(ot.rotateDeg.y);
    const Vec3 axis(std::cos(a), 0, -std::sin(a));  // the object's +x after the rotation about y
    t.translate = Vec3(ot.translate.x, size / 2, ot.translate.z) + axis * ((otherSize + size) / 2);
  } else if (mode == 3) {  // piercing it
    t.translate = Vec3(ot.translate.x + 0.45 * (otherSize + size), size / 2 + uniform(rng, 0, 0.3) * otherSize,
                       ot.translate.z + uniform(rng, -0.3, 0.3) * otherSize);
  }
  t.translate.x = std::clamp(t.translate.x, -range, range);
  t.translate.z = std::clamp(t.translate.z, -range, range);
  return t;
}

Edit randomEdit(const Scene& scene, std::mt19937_64& rng, int& nextNewId) {
  std::vector<const Object*> movable;
  for (const Object& o : scene.objects())
    if (isMovable(o)) movable.push_back(&o);
  const double r = uniform(rng, 0, 1);
  Edit edit;
  if (movable.empty() || r < 0.2) {
    edit.op = Edit::Op::Add;
    edit.object = unitCube("new_" + std::to_string(nextNewId++));
    edit.object.transform = placeCube(scene, rng, std::uniform_int_distribution<int>(16, 64)(rng) * kUnit, "");
    return edit;
  }
  const Object& target = *movable[std::uniform_int_distribution<size_t>(0, movable.size() - 1)(rng)];
  edit.id = target.id;
  if (r < 0.32) {
    edit.op = Edit::Op::Remove;
    return edit;
  }
  edit.op = Edit::Op::Move;
  edit.transform = target.transform;
  const double kind = uniform(rng, 0, 1);
  const double half = roomHalf(scene);
  if (kind < 0.35) {  // a small nudge, sometimes with a turn
    edit.transform.translate.x += uniform(rng, -4, 4) * kUnit;
    edit.transform.translate.z += uniform(rng, -4, 4) * kUnit;
    if (uniform(rng, 0, 1) < 0.3) edit.transform.rotateDeg.y += uniform(rng, -5, 5);
  } else if (kind < 0.5) {  // a turn about y only
    edit.transform.rotateDeg.y += uniform(rng, -45, 45);
  } else if (kind < 0.7 || !isCube(target)) {  // far across the room
    const double range = half - 1.0;
    edit.transform.translate.x = uniform(rng, -range, range);
    edit.transform.translate.z = uniform(rng, -range, range);
  } else {  // onto, beside or into another cube
    edit.transform = placeCube(scene, rng, target.transform.scale.x, target.id);
  }
  const double limit = half - 0.6;
  edit.transform.translate.x = std::clamp(edit.transform.translate.x, -limit, limit);
  edit.transform.translate.z = std::clamp(edit.transform.translate.z, -limit, limit);
  return edit;
}

}  // namespace

Vec3 centroid(const Polygon3& polygon) {
  Vec3 c(0.0);
  for (const Vec3& p : polygon) c += p;
  return c / double(polygon.size());
}

Polygon3 scaledMoved(const Polygon3& polygon, double scale, const Vec3& by) {
  const Vec3 c = centroid(polygon);
  Polygon3 out;
  for (const Vec3& p : polygon) out.push_back(c + scale * (p - c) + by);
  return out;
}

Edit moveEditBy(const Engine& engine, const std::string& id, const Vec3& by) {
  Edit edit;
  edit.op = Edit::Op::Move;
  edit.id = id;
  edit.transform = engine.scene().objects()[*engine.scene().findObject(id)].transform;
  edit.transform.translate += by;
  return edit;
}

Edit randomLightEdit(const Scene& scene, std::mt19937_64& rng, int& nextLightId) {
  const std::vector<Light>& lights = scene.lights();
  const Light& light = lights[std::uniform_int_distribution<size_t>(0, lights.size() - 1)(rng)];
  // To a random spot at the same height, inside the room (never drifting out of it).
  const double reach = 0.35 * roomHalf(scene);
  const Vec3 c = centroid(light.polygon);
  const Vec3 by(uniform(rng, -reach, reach) - c.x, 0, uniform(rng, -reach, reach) - c.z);
  const double r = uniform(rng, 0, 1);
  Edit edit;
  edit.id = light.id;
  if (r < 0.3 || (r < 0.6 && lights.size() == 1)) {  // a smaller copy elsewhere
    edit.op = Edit::Op::AddLight;
    edit.light = Light{"lamp_" + std::to_string(nextLightId++),
                       scaledMoved(light.polygon, uniform(rng, 0.3, 1.0), by),
                       light.radiance * uniform(rng, 0.5, 1.5)};
    edit.id = edit.light.id;
  } else if (r < 0.6) {
    edit.op = Edit::Op::RemoveLight;
  } else {
    edit.op = Edit::Op::SetLight;
    if (r < 0.85) edit.polygon = scaledMoved(light.polygon, 1.0, by);
    if (r >= 0.8) edit.radiance = light.radiance * uniform(rng, 0.5, 2.0);
  }
  return edit;
}

Frame randomLightFrame(const Engine& engine, std::mt19937_64& rng, size_t objectEdits,
                       int& nextNewId, int& nextLightId) {
  Frame frame;
  const size_t at = std::uniform_int_distribution<size_t>(0, objectEdits)(rng);
  for (size_t i = 0; i <= objectEdits; ++i) {
    const Scene working = engine.sceneAfter(frame);
    frame.edits.push_back(i == at ? randomLightEdit(working, rng, nextLightId)
                                  : randomEdit(working, rng, nextNewId));
  }
  return frame;
}

Frame randomFrame(const Engine& engine, std::mt19937_64& rng, size_t edits, int& nextNewId) {
  Frame frame;
  for (size_t i = 0; i < edits; ++i) {
    const Scene working = engine.sceneAfter(frame);
    frame.edits.push_back(randomEdit(working, rng, nextNewId));
  }
  return frame;
}

}  // namespace penumbra::testing
