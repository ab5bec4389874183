// Engine::apply: checking a frame, then updating the shadow state.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>

#include "core/engine/dirty_set.h"
#include "core/engine/engine.h"
#include "core/illum/face_lookup.h"

namespace penumbra {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// One object's faces: a contiguous run of Scene::faces(), which is sorted by id.
std::vector<Face> facesOfObject(const Scene& scene, uint32_t handle) {
  const auto& faces = scene.faces();
  auto it = std::lower_bound(faces.begin(), faces.end(), FaceId{handle, 0},
                             [](const Face& f, const FaceId& id) { return f.id < id; });
  std::vector<Face> out;
  for (; it != faces.end() && it->id.object == handle; ++it) out.push_back(*it);
  return out;
}

bool sameValue(const VertexIrradiance& a, const VertexIrradiance& b) {
  if (a.lightClass != b.lightClass) return false;
  for (int c = 0; c < 3; ++c)
    if (std::abs(a.irradiance[c] - b.irradiance[c]) > 1e-12 * std::max(std::abs(a.irradiance[c]), std::abs(b.irradiance[c])))
      return false;
  return true;
}

}  // namespace

Scene Engine::sceneAfter(const Frame& frame) const {
  // The overlap cubes are sound only for faces inside them (OverlapCube::insertFace).
  auto checkEditVolume = [&](const Scene& next, uint32_t handle, size_t i, const char* path) {
    for (const Face& face : facesOfObject(next, handle))
      if (!insideEditVolume(face))
        throw EditError(i, path, "object '" + next.object(handle).id + "' would leave the edit volume");
  };
  Scene next = scene_;
  for (size_t i = 0; i < frame.edits.size(); ++i) {
    const Edit& edit = frame.edits[i];
    try {
      switch (edit.op) {
        case Edit::Op::Move: {
          const auto index = next.findObject(edit.id);
          if (!index) throw EditError(i, "id", "unknown object '" + edit.id + "'");
          next.setTransform(next.handleOf(*index), edit.transform);
          checkEditVolume(next, next.handleOf(*index), i, "transform");
          break;
        }
        case Edit::Op::Remove: {
          const auto index = next.findObject(edit.id);
          if (!index) throw EditError(i, "id", "unknown object '" + edit.id + "'");
          next.removeObject(next.handleOf(*index));
          break;
        }
        case Edit::Op::Add:
          if (next.findObject(edit.object.id))
            throw EditError(i, "object.id", "duplicate object id '" + edit.object.id + "'");
          checkEditVolume(next, next.addObject(edit.object), i, "object");
          break;
      }
    } catch (const EditError&) {
      throw;
    } catch (const std::invalid_argument& error) {
      throw EditError(i, edit.op == Edit::Op::Add ? "object" : "transform", error.what());
    }
  }
  return next;
}

FrameResult Engine::apply(const Frame& frame) {
  Scene next = sceneAfter(frame);  // throws before anything changes

  // The frame's net effect per object handle (a move is remove + add, §3).
  std::set<uint32_t> oldHandles, newHandles, moved;
  for (size_t i = 0; i < scene_.objects().size(); ++i) oldHandles.insert(scene_.handleOf(i));
  for (size_t i = 0; i < next.objects().size(); ++i) newHandles.insert(next.handleOf(i));
  for (const Edit& edit : frame.edits)
    if (edit.op == Edit::Op::Move)
      if (const auto index = next.findObject(edit.id); index && oldHandles.count(next.handleOf(*index)))
        moved.insert(next.handleOf(*index));
  std::set<uint32_t> leaving = moved, entering = moved;  // handles whose faces leave / enter
  for (uint32_t h : oldHandles)
    if (!newHandles.count(h)) leaving.insert(h);
  for (uint32_t h : newHandles)
    if (!oldHandles.count(h)) entering.insert(h);
  std::vector<FaceId> leavingFaces;
  for (uint32_t h : leaving)
    for (const Face& face : facesOfObject(scene_, h)) leavingFaces.push_back(face.id);

  FrameResult result;
  DirtySet dirty;
  std::vector<FaceId> before;
  for (const Receiver& r : receivers_) before.push_back(r.face);
  scene_ = std::move(next);
  try {
    // REMOVE (§3.1): the leaving faces quit the orders and cubes, then every DM-tree
    // they shadowed loses their nodes and list entries.
    auto start = Clock::now();
    const size_t lightCount = scene_.lights().size();
    for (size_t l = 0; l < lightCount; ++l)
      for (FaceId face : leavingFaces) {
        orders_[l]->removeFace(face);
        cubes_[l]->removeFace(face);
      }
    std::vector<bool> dropped(receivers_.size(), false);
    std::set<FaceId> rebuild;       // receivers whose node deletion threw: cast afresh
    std::set<FaceId> rebuiltTrees;  // receivers whose tree rebuilt itself in a deletion
    for (FaceId face : leavingFaces) {
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
            const RemoveResult removed = tree.removeOccluder(uint32_t(l), face);
            if (!removed.found) continue;
            result.nodesDeleted += removed.nodesRemoved;
            dirty.markTopology(target);
            if (removed.rebuilt) {
              // The tree rebuilt itself from its stored shadows: every handle is new.
              rebuiltTrees.insert(target);
              dirty.forget(target);
              dirty.touch(target);
              dirty.markTopology(target);
              receiver.litAt.assign(receiver.litAt.size(), Vec2(std::numeric_limits<double>::quiet_NaN()));
              continue;
            }
            dirty.addCells(target, tree, removed.changedCells);
            dirty.addVertices(target, removed.newVertices);
          }
        } catch (const std::exception&) {
          rebuild.insert(target);
          dirty.forget(target);
        }
      }
      castOn_.erase(face);
      forgetReceived(face);
    }
    // The leaving objects' own trees go (a moved object's faces get fresh ones).
    for (size_t i = 0; i < receivers_.size(); ++i) {
      const FaceId face = receivers_[i].face;
      if (!leaving.count(face.object)) continue;
      dropped[i] = true;
      receiverIndex_.erase(face);
      dirty.forget(face);
      rebuild.erase(face);
      rebuiltTrees.erase(face);
    }
    for (FaceId face : rebuiltTrees)
      if (!rebuild.count(face)) ++result.treeRebuilds;
    result.seconds.remove = secondsSince(start);

    // ADD (§3.2): the entering faces join the orders and cubes, get DM-trees if they
    // receive light, and cast both ways with the faces sharing their tiles.
    start = Clock::now();
    std::vector<const Face*> enteringFaces;
    for (const Face& face : scene_.faces())
      if (entering.count(face.id.object)) enteringFaces.push_back(&face);
    for (size_t l = 0; l < lightCount; ++l)
      for (const Face* face : enteringFaces) {
        orders_[l]->insertFace(*face);
        cubes_[l]->insertFace(*face);
      }
    for (const Face* face : enteringFaces) {
      if (!scene_.receivesLight(*face)) continue;
      receiverIndex_[face->id] = receivers_.size();
      receivers_.push_back(makeReceiver(*face));
      dropped.push_back(false);
      dirty.touch(face->id);
      dirty.markTopology(face->id);
    }
    for (size_t l = 0; l < lightCount; ++l) {
      const FaceOrder& order = *orders_[l];
      std::set<std::tuple<size_t, size_t, FaceId, FaceId>> attempts;  // ranks, occluder, receiver
      for (const Face* face : enteringFaces) {
        if (!order.contains(face->id)) continue;
        for (FaceId other : cubes_[l]->candidates(face->id)) {
          if (!order.contains(other)) continue;
          attempts.insert({order.rank(face->id), order.rank(other), face->id, other});
          attempts.insert({order.rank(other), order.rank(face->id), other, face->id});
        }
      }
      for (const auto& [occluderRank, receiverRank, occluder, target] : attempts) {
        const auto found = receiverIndex_.find(target);
        if (found == receiverIndex_.end() || rebuild.count(target)) continue;
        Receiver& receiver = receivers_[found->second];
        const auto inserted = castPair(l, *findFace(scene_, occluder), receiver);
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
      receiver = makeReceiver(*findFace(scene_, target));
      castAllOn(receiver);
      dirty.touch(target);
      dirty.markTopology(target);
      ++result.treeRebuilds;
    }
    result.seconds.add = secondsSince(start);

    // RELIGHT (§3.3): once, every vertex in the set, plus any live vertex whose slot
    // holds no value for its position (a vertex the tree did not report as new).
    start = Clock::now();
    lastRelit_.clear();
    for (const auto& [face, vertices] : dirty.receivers()) {
      Receiver& receiver = receivers_[receiverIndex_.at(face)];
      const HalfEdgeMesh& mesh = receiver.tree.mesh();
      const size_t known = receiver.values.size();
      growSlots(receiver);
      std::set<VertexId> relight;
      for (VertexId v : vertices)
        if (v.index < mesh.vertexSlots() && mesh.vertex(v).alive) relight.insert(v);
      for (VertexId v : receiver.tree.vertices())
        if (receiver.litAt[v.index] != receiver.tree.position(v)) relight.insert(v);
      for (VertexId v : relight) {
        const bool fresh = v.index >= known || receiver.litAt[v.index] != receiver.tree.position(v);
        const VertexIrradiance old = receiver.values[v.index];
        relightVertex(receiver, v);
        ++result.verticesRelit;
        if (fresh) ++result.verticesCreated;
        if (fresh || !sameValue(old, receiver.values[v.index])) ++result.verticesChanged;
      }
      if (!relight.empty() || dirty.topologyChanged(face)) result.changedReceivers.push_back(face);
      if (!relight.empty()) lastRelit_[face] = std::vector<VertexId>(relight.begin(), relight.end());
    }
    result.seconds.relight = secondsSince(start);
    compactReceivers(dropped);
  } catch (const std::exception&) {
    // Unexpected (an insert refused, a cube or order failing): the whole engine is
    // rebuilt for the new scene so no half-edited state survives.
    const auto start = Clock::now();
    const uint64_t version = version_;
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
  }

  std::sort(result.changedReceivers.begin(), result.changedReceivers.end());
  for (FaceId face : before)
    if (!receiver(face)) result.removedReceivers.push_back(face);
  result.version = ++version_;
  return result;
}

}  // namespace penumbra
