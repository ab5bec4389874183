// Engine::apply: a checked frame planned, then the paper's three phases (remove, add, relight:
// frame_remove.cpp, frame_add.cpp, frame_relight.cpp), or one whole rebuild where that is
// cheaper or the lights moved.
#include <algorithm>
#include <chrono>
#include <new>
#include <set>
#include <span>

#include "core/engine/engine.h"
#include "core/engine/light_edits.h"
#include "core/engine/seconds_since.h"
#include "core/engine/volume_edits.h"
#include "core/illum/face_lookup.h"
#include "core/shadow/object_shadow.h"

namespace penumbra {

namespace {

// The switch to a full rebuild (FrameResult::fullRebuild) counts work, not faces: a frame
// whose leaving objects take part in more than this share of the engine's cast pairs
// (occluder → receiver, castOn) rebuilds, in scenes large enough that a rebuild is not the
// cheap path anyway (small scenes, the property tests', stay incremental). The pairs counted
// are those the frame undoes (the leaving faces and whole objects as occluders, the trees of
// the leaving receivers); it redoes about as many. Measured (penumbra replay with the
// switch forced either way, 2 threads, a quiet machine): moving 5 / 10 / 30 % of the 150-cube
// room's cubes undoes 0.08 / 0.15 / 0.43 of the pairs and costs 0.35 / 0.66 / 1.81 of a
// rebuild (about 4.2 × the share: even at 0.24); cubes15 0.05 / 0.12 / 0.57 cost 0.15 / 0.34 /
// 1.81 (even at 0.3); dragging a 1,000-triangle teapot in the room undoes 2.0 and cost 5.4
// rebuilds.
constexpr double kFullRebuildPairShare = 0.25;
constexpr size_t kFullRebuildMinFaces = 400;
// Objects a frame adds (not moves) have no pairs yet to count: adding more than this share of
// the faces rebuilds (measured on 'cubes' scenes: adding or moving 10% of N = 150 costs ~0.4 of
// a rebuild, 30% ~2×).
constexpr double kFullRebuildAddedShare = 0.15;

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
      case Edit::Op::SetMaterial:
        scene.setMaterial(edit.material);
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
    if (edit.op == Edit::Op::SetMaterial) continue;  // nor materials
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

FramePlan Engine::planFrame(const Frame& frame) {
  // From the objects the frame's edits name: the scene is edited in place, nothing here
  // scans or copies the whole scene.
  FramePlan plan;
  plan.leaving = namedHandles(scene_, frame);
  for (uint32_t h : plan.leaving)
    for (const Face& face : scene_.facesOfObject(h)) plan.leavingFaces.push_back(face.id);
  for (FaceId face : plan.leavingFaces)
    if (receiverIndex_.count(face)) plan.leavingReceivers.push_back(face);
  if (changesRadiance(frame))  // values are summed with the radiances on each read
    for (const Light& light : scene_.lights()) plan.radianceBefore.push_back(light.radiance);
  plan.lightMoved = reshapesLights(frame);
  if (plan.lightMoved)
    for (const Receiver& r : receivers_) plan.receiversBefore.push_back(r.face);
  applyEdits(scene_, frame);
  plan.entering = namedHandles(scene_, frame);
  size_t addedFaces = 0;
  for (uint32_t h : plan.entering)
    if (!plan.leaving.count(h)) addedFaces += scene_.facesOfObject(h).size();
  const size_t faces = scene_.faces().size();
  plan.largeFrame = faces >= kFullRebuildMinFaces &&
                    (double(castPairsUndone(plan)) > kFullRebuildPairShare * double(castPairs()) ||
                     double(addedFaces) > kFullRebuildAddedShare * double(faces));
  return plan;
}

size_t Engine::castPairs() const {
  size_t pairs = 0;
  for (const auto& [occluder, receivers] : castOn_) pairs += receivers.size();
  return pairs;
}

size_t Engine::castPairsUndone(const FramePlan& plan) const {
  size_t pairs = 0;
  auto add = [&](const std::map<FaceId, std::set<FaceId>>& relation, FaceId face) {
    if (const auto it = relation.find(face); it != relation.end()) pairs += it->second.size();
  };
  for (FaceId face : plan.leavingFaces) add(castOn_, face);
  for (uint32_t h : plan.leaving) add(castOn_, wholeObject(h));
  for (FaceId face : plan.leavingReceivers) add(castBy_, face);
  return pairs;
}

FrameResult Engine::rebuildWhole() {
  const auto start = std::chrono::steady_clock::now();
  const uint64_t version = version_;
  reach("rebuild");
  Engine rebuilt(scene_, settings_);
  *this = std::move(rebuilt);
  version_ = version;
  FrameResult result;
  for (const Receiver& r : receivers_) {
    result.changedReceivers.push_back(r.face);
    result.verticesRelit += r.tree.vertexCount();
  }
  result.verticesChanged = result.verticesCreated = result.verticesRelit;
  result.treeRebuilds = receivers_.size();
  result.seconds.add = secondsSince(start);
  lastRelit_.clear();
  for (Receiver& r : receivers_) lastRelit_[r.face] = r.tree.vertices();
  return result;
}

FrameResult Engine::apply(const Frame& frame) {
  if (!usable_) throw std::logic_error("Engine: unusable after a failed frame; rebuild it from the previous scene");
  checkFrame(frame);  // throws before anything changes
  usable_ = false;    // until the frame completes
  const FramePlan plan = planFrame(frame);
  FrameResult result;
  if (plan.incremental()) try {
    FrameWork work;
    removeLeaving(plan, work, result);
    reach("removed");
    addEntering(plan, work, result);
    reach("added");
    relightDirty(work, result);
    // Compact only if a receiver left for good or one joined out of face order.
    const bool anyDropped = std::find(work.dropped.begin(), work.dropped.end(), true) != work.dropped.end();
    if (anyDropped || work.appendedOutOfOrder) compactReceivers(work.dropped);
    recountBudget();
    // A new radiance changes no shadow: values are summed on each read; what changed is reported.
    if (changesRadiance(frame)) resumRadiance(plan.radianceBefore, result);
  } catch (const ResourceLimitError&) {
    throw;  // usable_ stays false: the caller rebuilds from the previous scene
  } catch (const std::bad_alloc&) {
    throw;  // no memory: the caller restores the previous state (SceneSession)
  } catch (const std::exception&) {
    // Unexpected (an insert refused, a cube or order failing): the whole engine is
    // rebuilt for the new scene so no half-edited state survives.
    result = rebuildWhole();
  }
  if (!plan.incremental()) {
    result = rebuildWhole();
    result.fullRebuild = true;
  }
  result.radianceChanged = changesRadiance(frame);

  std::sort(result.changedReceivers.begin(), result.changedReceivers.end());
  for (FaceId face : plan.leavingReceivers)
    if (!receiver(face)) result.removedReceivers.push_back(face);
  for (FaceId face : plan.receiversBefore)  // faces the lights no longer reach
    if (!receiver(face) && findFace(scene_, face)) result.removedReceivers.push_back(face);
  result.version = ++version_;
  usable_ = true;
  return result;
}

}  // namespace penumbra
