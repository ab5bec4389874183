// Engine::apply: checking a frame, then updating the shadow state.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <new>
#include <optional>
#include <set>
#include <span>
#include <tuple>

#include "core/engine/dirty_set.h"
#include "core/engine/engine.h"
#include "core/engine/light_edits.h"
#include "core/engine/volume_edits.h"
#include "core/illum/face_lookup.h"
#include "core/shadow/object_shadow.h"

namespace penumbra {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A copy of one object's faces (the scene changes after it is taken).
std::vector<Face> facesOfObject(const Scene& scene, uint32_t handle) {
  const std::span<const Face> faces = scene.facesOfObject(handle);
  return {faces.begin(), faces.end()};
}

// The switch to a full rebuild (FrameResult::fullRebuild): frames editing more than
// this share of the faces, in scenes large enough that a rebuild is not the cheap
// path anyway (small scenes, the property tests', stay incremental). Measured on
// 'cubes' scenes (penumbra-bench edits): moving 10% of N = 150 costs ~0.4 of a
// rebuild, 30% ~2×; at N = 1500 the crossing comes earlier.
constexpr double kFullRebuildShare = 0.15;
// EngineSettings::failurePoint, when set (tests).
void reach(const EngineSettings& settings, const char* point) {
  if (settings.failurePoint) settings.failurePoint(point);
}
constexpr size_t kFullRebuildMinFaces = 400;

// The last edit giving a light a new polygon, or adding one (a frame with none: 0).
size_t lastLightMove(const Frame& frame) {
  size_t last = 0;
  for (size_t i = 0; i < frame.edits.size(); ++i) {
    const Edit& edit = frame.edits[i];
    if ((edit.op == Edit::Op::SetLight && edit.polygon) || edit.op == Edit::Op::AddLight) last = i;
  }
  return last;
}

// A frame reshaping the lights rebuilds every cube around them: the faces the frame leaves
// alone must lie in the new cubes too (OverlapCube::insertFace refuses others).
void checkUneditedFaces(const Scene& scene, const Frame& frame, const std::set<std::string, std::less<>>& edited,
                        const std::vector<OverlapCube::Box>& cubes) {
  for (const Face& face : scene.faces()) {
    const Object& object = scene.object(face.id.object);
    if (edited.count(object.id) || insideCubes(scene, face.polygon, cubes)) continue;
    const size_t i = lastLightMove(frame);
    const bool added = frame.edits[i].op == Edit::Op::AddLight;
    throw EditError(i, added ? "light.polygon" : "polygon",
                    "light '" + (added ? frame.edits[i].light.id : frame.edits[i].id) + "' would leave object '" + object.id +
                        "' outside its overlap cube (the lights' cubes enclose the scene)");
  }
}

}  // namespace

void Engine::checkFrame(const Frame& frame) const {
  // The ids the frame has edited so far, as the earlier edits leave them (empty: removed).
  std::map<std::string, std::optional<Object>, std::less<>> edited;
  auto current = [&](const std::string& id) -> std::optional<Object> {
    if (const auto it = edited.find(id); it != edited.end()) return it->second;
    if (const auto index = scene_.findObject(id)) return scene_.objects()[*index];
    return std::nullopt;
  };
  // The overlap cubes are sound only for faces inside them (OverlapCube::insertFace): the
  // current ones, or those of the lights as the frame leaves them (a frame moving, adding
  // or removing a light rebuilds every cube).
  const bool lightMoved = reshapesLights(frame);
  std::vector<OverlapCube::Box> cubes;
  if (lightMoved) {
    cubes = cubesFor(scene_, lightsAfter(scene_, frame));
  } else {
    for (const auto& cube : cubes_) cubes.push_back({cube->cubeMin(), cube->cubeSide()});
  }
  std::vector<Light> lights = scene_.lights();  // as the frame's earlier light edits leave them
  // Faces as Scene::addObject / setTransform would make them (throws std::invalid_argument).
  auto checkFaces = [&](const Object& object, size_t i, const char* path) {
    for (const Face& face : scene_.facesOf(object, 0))
      if (!insideCubes(scene_, face.polygon, cubes))
        throw EditError(i, path, "object '" + object.id + "' would leave the edit volume");
  };
  VolumeEditCheck volumes(scene_);  // volumes as the frame's earlier edits leave them
  auto objectExists = [&](const std::string& id) { return current(id).has_value(); };
  for (size_t i = 0; i < frame.edits.size(); ++i) {
    const Edit& edit = frame.edits[i];
    try {
      if (volumes.concerns(edit)) {  // render-time only: no faces, no cubes
        volumes.check(edit, i, objectExists);
        continue;
      }
      switch (edit.op) {
        case Edit::Op::Move: {
          std::optional<Object> object = current(edit.id);
          if (!object) throw EditError(i, "id", "unknown object '" + edit.id + "'");
          object->transform = edit.transform;
          checkFaces(*object, i, "transform");
          edited[edit.id] = std::move(object);
          break;
        }
        case Edit::Op::Remove:
          if (!current(edit.id)) throw EditError(i, "id", "unknown object '" + edit.id + "'");
          edited[edit.id] = std::nullopt;
          break;
        case Edit::Op::Add:
          if (current(edit.object.id) || volumes.has(edit.object.id))
            throw EditError(i, "object.id", "duplicate object id '" + edit.object.id + "'");
          checkFaces(edit.object, i, "object");
          edited[edit.object.id] = edit.object;
          break;
        case Edit::Op::SetLight:
        case Edit::Op::AddLight:
        case Edit::Op::RemoveLight:
          checkLightEdit(scene_, edit, i, lights);
          break;
        case Edit::Op::SetVolume:
        case Edit::Op::AddVolume:
          break;  // volumes.concerns() took them
      }
    } catch (const EditError&) {
      throw;
    } catch (const FaceError& error) {
      // An added object's face has a key path; a moved one is refused for its transform.
      if (edit.op == Edit::Op::Add)
        throw EditError(i, "object.faces[" + std::to_string(error.face()) + "]", error.problem());
      throw EditError(i, "transform", error.what());
    } catch (const std::invalid_argument& error) {
      throw EditError(i, edit.op == Edit::Op::Add ? "object" : "transform", error.what());
    }
  }
  if (lightMoved) {
    std::set<std::string, std::less<>> ids;
    for (const auto& [id, object] : edited) ids.insert(id);
    checkUneditedFaces(scene_, frame, ids, cubes);
  }
  size_t faces = scene_.faces().size();
  for (const auto& [id, object] : edited) {
    if (const auto index = scene_.findObject(id)) faces -= scene_.objects()[*index].faces.size();
    if (object) faces += object->faces.size();
  }
  budget_.checkFaces(faces);
}

namespace {

// Applies a checked frame's edits to `scene` in order.
void applyEdits(Scene& scene, const Frame& frame) {
  for (const Edit& edit : frame.edits) {
    const bool volumeEdit =
        edit.op == Edit::Op::SetVolume || edit.op == Edit::Op::AddVolume ||
        ((edit.op == Edit::Op::Move || edit.op == Edit::Op::Remove) && scene.findVolume(edit.id));
    if (volumeEdit) {
      applyVolumeEdit(scene, edit);
      continue;
    }
    switch (edit.op) {
      case Edit::Op::Move:
        scene.setTransform(scene.handleOf(*scene.findObject(edit.id)), edit.transform);
        break;
      case Edit::Op::Remove:
        scene.removeObject(scene.handleOf(*scene.findObject(edit.id)));
        break;
      case Edit::Op::Add:
        scene.addObject(edit.object);
        break;
      case Edit::Op::SetLight:
      case Edit::Op::AddLight:
      case Edit::Op::RemoveLight:
        applyLightEdit(scene, edit);
        break;
      case Edit::Op::SetVolume:
      case Edit::Op::AddVolume:
        break;  // applied above
    }
  }
}

// The handles of the objects a frame's edits name, in `scene` (those it holds).
std::set<uint32_t> namedHandles(const Scene& scene, const Frame& frame) {
  std::set<uint32_t> out;
  for (const Edit& edit : frame.edits) {
    if (isLightEdit(edit)) continue;  // lights are no objects
    if (edit.op == Edit::Op::SetVolume || edit.op == Edit::Op::AddVolume) continue;  // nor volumes
    if (const auto index = scene.findObject(edit.op == Edit::Op::Add ? edit.object.id : edit.id))
      out.insert(scene.handleOf(*index));
  }
  return out;
}

}  // namespace

Scene Engine::sceneAfter(const Frame& frame) const {
  checkFrame(frame);
  Scene next = scene_;
  applyEdits(next, frame);
  return next;
}

void Engine::relightAfterRemoval(FaceId target, Receiver& receiver, const RemoveResult& removed, DirtySet& dirty) {
  const DmTree& tree = receiver.tree;
  const HalfEdgeMesh& mesh = tree.mesh();
  const double eps = scene_.tolerance().length();
  dirty.noteValueSlots(target, receiver.perLight.size());
  growSlots(receiver);
  dirty.touch(target);
  // Deleted vertices that held a current value for their position (not waiting to be
  // relit after an earlier deletion of this frame), by exact position.
  std::vector<std::tuple<double, double, uint32_t>> deleted;  // (x, y, slot), sorted
  for (VertexId v : removed.removedVertices) {
    const Vec2 p = tree.position(v);
    if (v.index < receiver.lit.size() && receiver.lit[v.index] && !dirty.pending(target, v))
      deleted.emplace_back(p.x, p.y, v.index);
  }
  std::sort(deleted.begin(), deleted.end());
  auto deletedAt = [&](const Vec2& p) -> std::optional<uint32_t> {
    const auto it = std::lower_bound(deleted.begin(), deleted.end(), std::tuple(p.x, p.y, uint32_t(0)));
    if (it == deleted.end() || std::get<0>(*it) != p.x || std::get<1>(*it) != p.y) return std::nullopt;
    return std::get<2>(*it);
  };
  // The penumbra's box first: most re-split cells lie far from it.
  Vec2 boxMin(INFINITY), boxMax(-INFINITY);
  for (const Vec2& q : removed.penumbra) {
    boxMin = glm::min(boxMin, q - Vec2(eps));
    boxMax = glm::max(boxMax, q + Vec2(eps));
  }
  auto inPenumbra = [&](const Vec2& p) {
    if (removed.penumbra.empty()) return true;
    if (glm::any(glm::lessThan(p, boxMin)) || glm::any(glm::greaterThan(p, boxMax))) return false;
    return contains(removed.penumbra, p, eps);
  };
  std::vector<bool> seen(mesh.vertexSlots(), false);
  auto settle = [&](VertexId v) {
    if (v.index >= mesh.vertexSlots() || seen[v.index] || !mesh.vertex(v).alive) return;
    seen[v.index] = true;
    const Vec2 p = tree.position(v);
    if (inPenumbra(p)) return dirty.addVertex(target, v);
    if (receiver.lit[v.index]) return;  // a survivor: its value stands
    const std::optional<uint32_t> was = deletedAt(p);
    if (!was) return dirty.addVertex(target, v);
    std::ranges::copy(receiver.perLight[*was], receiver.perLight[v.index].begin());
    receiver.lit[v.index] = 1;
    for (CellId c : tree.cellsAround(v)) receiver.tree.touch(c);  // corner values for meshing
  };
  std::vector<CellId> cells = removed.changedCells;
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  for (CellId c : cells) {
    if (c.index >= mesh.cellSlots() || !mesh.cell(c).alive) continue;
    const HalfEdgeId first = mesh.cell(c).edge;
    HalfEdgeId h = first;
    do {
      settle(mesh.halfEdge(h).origin);
      h = mesh.halfEdge(h).next;
    } while (h != first);
  }
  for (VertexId v : removed.newVertices) settle(v);
}

FrameResult Engine::apply(const Frame& frame) {
  if (!usable_) throw std::logic_error("Engine: unusable after a failed frame; rebuild it from the previous scene");
  checkFrame(frame);  // throws before anything changes
  usable_ = false;    // until the frame completes
  const size_t lights = scene_.lights().size();

  // The frame's net effect per object handle (a move is remove + add, §3), from the
  // objects its edits name: the scene is edited in place, nothing here scans or copies
  // the whole scene. Every named object that was there leaves (a no-op move is still
  // re-cast); every named object there afterwards enters.
  const std::set<uint32_t> leaving = namedHandles(scene_, frame);
  std::vector<FaceId> leavingFaces;
  for (uint32_t h : leaving)
    for (const Face& face : facesOfObject(scene_, h)) leavingFaces.push_back(face.id);

  FrameResult result;
  DirtySet dirty;
  std::vector<FaceId> leavingReceivers;  // leaving faces that had a DM-tree
  for (FaceId face : leavingFaces)
    if (receiverIndex_.count(face)) leavingReceivers.push_back(face);
  std::vector<Vec3> radianceBefore;  // values are summed with the radiances on each read
  if (changesRadiance(frame))
    for (const Light& light : scene_.lights()) radianceBefore.push_back(light.radiance);
  applyEdits(scene_, frame);
  const std::set<uint32_t> entering = namedHandles(scene_, frame);
  // Builds the whole engine for the new scene and reports every receiver as rebuilt.
  auto rebuildAll = [&] {
    const auto start = Clock::now();
    const uint64_t version = version_;
    reach(settings_, "rebuild");
    Engine rebuilt(scene_, settings_);
    *this = std::move(rebuilt);
    version_ = version;
    result = FrameResult{};
    for (const Receiver& r : receivers_) {
      result.changedReceivers.push_back(r.face);
      result.verticesRelit += r.tree.vertexCount();
    }
    result.verticesChanged = result.verticesCreated = result.verticesRelit;
    result.treeRebuilds = receivers_.size();
    result.seconds.add = secondsSince(start);
    lastRelit_.clear();
    for (Receiver& r : receivers_) lastRelit_[r.face] = r.tree.vertices();
  };
  // A frame moving a large share of the faces costs more than a rebuild (their
  // shadows on each other go twice): switch to one (FrameResult::fullRebuild).
  size_t enteringCount = 0;
  for (uint32_t h : entering) enteringCount += facesOfObject(scene_, h).size();
  const size_t faceCount = scene_.faces().size();
  const bool largeFrame = faceCount >= kFullRebuildMinFaces &&
                          double(std::max(leavingFaces.size(), enteringCount)) > kFullRebuildShare * double(faceCount);
  // A moved, resized, turned, added or removed light changes the orders, the cubes, every
  // shadow it casts, the per-light values and which faces receive at all: the engine is
  // rebuilt (counted as fullRebuild).
  const bool lightMoved = reshapesLights(frame);
  std::vector<FaceId> receiversBefore;
  if (lightMoved)
    for (const Receiver& r : receivers_) receiversBefore.push_back(r.face);
  if (!largeFrame && !lightMoved) try {
    // REMOVE (§3.1): the leaving faces quit the orders and cubes, then every DM-tree
    // they shadowed loses their nodes and list entries.
    auto start = Clock::now();
    const size_t lightCount = scene_.lights().size();
    for (size_t l = 0; l < lightCount; ++l)
      for (FaceId face : leavingFaces) {
        orders_[l]->removeFace(face);
        cubes_[l]->removeFace(face);
      }
    // Receivers of leaving faces are dropped; a moved face's slot is reused for its
    // new tree, so a move does not reorder the receivers.
    std::vector<bool> dropped(receivers_.size(), false);
    std::map<FaceId, size_t> freeSlots;
    std::set<FaceId> rebuild;       // receivers whose node deletion threw: cast afresh
    std::set<FaceId> rebuiltTrees;  // receivers whose tree rebuilt itself in a deletion
    // The leaving occluders: their faces and, for those that cast whole, the objects.
    std::vector<FaceId> leavingOccluders = leavingFaces;
    for (uint32_t h : leaving) leavingOccluders.push_back(wholeObject(h));
    for (FaceId face : leavingOccluders) {
      const auto on = castOn_.find(face);
      const std::set<FaceId> shadowed = on == castOn_.end() ? std::set<FaceId>{} : on->second;
      for (FaceId target : shadowed) {
        if (const auto by = castBy_.find(target); by != castBy_.end()) by->second.erase(face);
        if (leaving.count(target.object) || rebuild.count(target)) continue;  // dropped or rebuilt anyway
        Receiver& receiver = receivers_[receiverIndex_.at(target)];
        DmTree& tree = receiver.tree;
        dirty.touch(target);
        // changedCells holds the cells that lost the face and those whose outline
        // changed (a merged cell's survivor among them), so every vertex whose
        // surrounding lists changed is on a live one.
        try {
          for (size_t l = 0; l < lightCount; ++l) {
            const TreeUsage before = usageOf(tree, lights);
            const RemoveResult removed = tree.removeOccluder(uint32_t(l), face);
            budget_.change(before, usageOf(tree, lights));
            if (!removed.found) continue;
            result.nodesDeleted += removed.nodesRemoved;
            dirty.markTopology(target);
            if (removed.rebuilt) {
              // The tree rebuilt itself from its stored shadows: every handle is new.
              rebuiltTrees.insert(target);
              dirty.forget(target);
              dirty.touch(target);
              dirty.markTopology(target);
              receiver.lit.assign(receiver.lit.size(), 0);
              continue;
            }
            relightAfterRemoval(target, receiver, removed, dirty);
          }
        } catch (const ResourceLimitError&) {
          throw;  // a budget, not a geometric failure: never retried
        } catch (const std::bad_alloc&) {
          throw;  // no memory: a bigger rebuild would not help, the caller restores
        } catch (const std::exception&) {
          rebuild.insert(target);
          dirty.forget(target);
        }
      }
      castOn_.erase(face);
      forgetReceived(face);
    }
    // The leaving objects' own trees go (a moved object's faces get fresh ones).
    for (FaceId face : leavingReceivers) {
      const size_t i = receiverIndex_.at(face);
      budget_.change(usageOf(receivers_[i].tree, lights), {});
      dropped[i] = true;
      freeSlots[face] = i;
      receiverIndex_.erase(face);
      dirty.forget(face);
      rebuild.erase(face);
      rebuiltTrees.erase(face);
    }
    for (FaceId face : rebuiltTrees)
      if (!rebuild.count(face)) ++result.treeRebuilds;
    result.seconds.remove = secondsSince(start);
    reach(settings_, "removed");

    // ADD (§3.2): the entering faces join the orders and cubes, get DM-trees if they
    // receive light, and cast both ways with the faces sharing their tiles.
    start = Clock::now();
    std::vector<const Face*> enteringFaces;
    for (uint32_t h : entering)
      for (const Face& face : scene_.facesOfObject(h)) enteringFaces.push_back(&face);
    for (size_t l = 0; l < lightCount; ++l)
      for (const Face* face : enteringFaces) {
        orders_[l]->insertFace(*face);
        cubes_[l]->insertFace(*face);
      }
    bool appendedOutOfOrder = false;
    for (const Face* face : enteringFaces) {
      if (!scene_.receivesLight(*face)) continue;
      if (const auto slot = freeSlots.find(face->id); slot != freeSlots.end()) {
        receivers_[slot->second] = makeReceiver(*face);
        budget_.change({}, usageOf(receivers_[slot->second].tree, lights));
        dropped[slot->second] = false;
        receiverIndex_[face->id] = slot->second;
        freeSlots.erase(slot);
      } else {
        appendedOutOfOrder |= !receivers_.empty() && !(receivers_.back().face < face->id);
        receiverIndex_[face->id] = receivers_.size();
        receivers_.push_back(makeReceiver(*face));
        budget_.change({}, usageOf(receivers_.back().tree, lights));
        dropped.push_back(false);
      }
      dirty.touch(face->id);
      dirty.markTopology(face->id);
    }
    for (size_t l = 0; l < lightCount; ++l) {
      const FaceOrder& order = *orders_[l];
      // Front-to-back ranks among the faces involved only (FaceOrder::walkKey), so the
      // whole walk is not rebuilt for each frame.
      std::vector<std::pair<FaceId, FaceId>> pairs;  // (entering face, candidate)
      std::map<FaceId, FaceOrder::WalkKey> keys;
      for (const Face* face : enteringFaces) {
        if (!order.contains(face->id)) continue;
        keys[face->id];
        for (FaceId other : cubes_[l]->candidates(face->id)) {
          // Faces of one closed convex object never shadow each other (as in the build).
          if (!order.contains(other) || !scene_.mayShadow(face->id, other)) continue;
          keys[other];
          pairs.push_back({face->id, other});
        }
      }
      std::vector<std::pair<FaceOrder::WalkKey, FaceId>> byKey;
      for (auto& [face, key] : keys) byKey.push_back({order.walkKey(face), face});
      std::sort(byKey.begin(), byKey.end());
      std::map<FaceId, size_t> rank;
      for (size_t i = 0; i < byKey.size(); ++i) rank[byKey[i].second] = i;
      std::set<std::tuple<size_t, size_t, FaceId, FaceId>> attempts;  // ranks, occluder, receiver
      for (const auto& [face, other] : pairs) {
        attempts.insert({rank.at(face), rank.at(other), face, other});
        attempts.insert({rank.at(other), rank.at(face), other, face});
      }
      std::set<std::pair<FaceId, FaceId>> cast;  // a whole object casts once, at its first face's rank
      for (const auto& [occluderRank, receiverRank, occluder, target] : attempts) {
        const auto found = receiverIndex_.find(target);
        if (found == receiverIndex_.end() || rebuild.count(target)) continue;
        const FaceId caster =
            castingOccluder(scene_, l, occluder, *findFace(scene_, target), settings_.closedObjectsAsOne);
        if (!cast.insert({caster, target}).second) continue;
        Receiver& receiver = receivers_[found->second];
        const auto inserted = castPair(l, caster, receiver);
        if (!inserted) continue;
        dirty.touch(target);
        if (inserted->nodesAdded || !inserted->newVertices.empty()) dirty.markTopology(target);
        dirty.addCells(target, receiver.tree, inserted->changedCells);
        dirty.addVertices(target, inserted->newVertices);
      }
    }
    // Fallback: receivers whose node deletion failed get their tree cast afresh.
    for (FaceId target : rebuild) {
      Receiver& receiver = receivers_[receiverIndex_.at(target)];
      forgetReceived(target);
      budget_.change(usageOf(receiver.tree, lights), {});
      receiver = makeReceiver(*findFace(scene_, target));
      budget_.change({}, usageOf(receiver.tree, lights));
      castAllOn(receiver);
      dirty.touch(target);
      dirty.markTopology(target);
      ++result.treeRebuilds;
    }
    result.seconds.add = secondsSince(start);
    reach(settings_, "added");

    // RELIGHT (§3.3): once, every vertex in the set, plus any live vertex whose slot
    // holds no value for its position (a vertex the tree did not report as new).
    start = Clock::now();
    lastRelit_.clear();
    for (const auto& [face, vertices] : dirty.receivers()) {
      reach(settings_, "relight");
      Receiver& receiver = receivers_[receiverIndex_.at(face)];
      const HalfEdgeMesh& mesh = receiver.tree.mesh();
      const size_t known = dirty.valueSlots(face, receiver.perLight.size());
      growSlots(receiver);
      std::set<VertexId> relight;
      for (VertexId v : vertices)
        if (v.index < mesh.vertexSlots() && mesh.vertex(v).alive) relight.insert(v);
      // Vertex slots are append-only and positions never change, so only slots past
      // `known` can hold an unlit vertex, unless the tree was rebuilt (slots reused).
      const bool rebuiltTree = rebuiltTrees.count(face) || rebuild.count(face);
      for (uint32_t i = rebuiltTree ? 0 : uint32_t(std::min(known, mesh.vertexSlots())); i < mesh.vertexSlots(); ++i) {
        const VertexId v(i);
        if (mesh.vertex(v).alive && !receiver.lit[i]) relight.insert(v);
      }
      for (VertexId v : relight) {
        const bool fresh = v.index >= known || !receiver.lit[v.index];
        const VertexIrradiance old = fresh ? VertexIrradiance{} : value(receiver, v);
        relightVertex(receiver, v);
        ++result.verticesRelit;
        if (fresh) ++result.verticesCreated;
        if (fresh || !sameValue(old, value(receiver, v))) ++result.verticesChanged;
      }
      if (!relight.empty() || dirty.topologyChanged(face)) result.changedReceivers.push_back(face);
      if (!relight.empty()) lastRelit_[face] = std::vector<VertexId>(relight.begin(), relight.end());
    }
    result.seconds.relight = secondsSince(start);
    // Compact only if a receiver left for good or one joined out of face order.
    const bool anyDropped = std::find(dropped.begin(), dropped.end(), true) != dropped.end();
    if (anyDropped || appendedOutOfOrder) compactReceivers(dropped);
    recountBudget();
    // A new radiance changes no shadow: values are summed on each read; what changed is reported.
    if (changesRadiance(frame)) resumRadiance(radianceBefore, result);
  } catch (const ResourceLimitError&) {
    throw;  // usable_ stays false: the caller rebuilds from the previous scene
  } catch (const std::bad_alloc&) {
    throw;  // no memory: the caller restores the previous state (SceneSession)
  } catch (const std::exception&) {
    // Unexpected (an insert refused, a cube or order failing): the whole engine is
    // rebuilt for the new scene so no half-edited state survives.
    rebuildAll();
  }
  if (largeFrame || lightMoved) {
    rebuildAll();
    result.fullRebuild = true;
  }
  result.radianceChanged = changesRadiance(frame);

  std::sort(result.changedReceivers.begin(), result.changedReceivers.end());
  for (FaceId face : leavingReceivers)
    if (!receiver(face)) result.removedReceivers.push_back(face);
  for (FaceId face : receiversBefore)  // faces the lights no longer reach
    if (!receiver(face) && findFace(scene_, face)) result.removedReceivers.push_back(face);
  result.version = ++version_;
  usable_ = true;
  return result;
}

}  // namespace penumbra
