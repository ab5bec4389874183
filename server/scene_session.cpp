#include "server/scene_session.h"

#include <map>
#include <set>
#include <stdexcept>

#include "core/engine/seconds_since.h"
#include "server/limits.h"
#include "server/part_diff.h"

namespace penumbra::server {

namespace {

// The engine's chunks of some receivers as parts, all at `version`.
std::vector<MeshPart> partsOf(const Scene& scene, const Engine::ReceiverChunks& receiver, uint64_t version) {
  std::vector<MeshPart> out;
  const ReceiverKey key{scene.object(receiver.face.object).id, receiver.face.face};
  for (const Engine::MeshChunk& chunk : receiver.chunks)
    out.push_back({{key, chunk.key.x, chunk.key.y}, chunk.mesh, version, version});
  return out;
}

}  // namespace

SceneSession::SceneSession(std::string id, std::string name, Scene scene, EngineSettings settings,
                           const EngineProgress& progress)
    : id_(std::move(id)), settings_(settings) {
  baseScene_ = scene;
  for (const VolumeObject& volume : scene.volumes()) initialVolumeFiles_.push_back(volume.file);
  engine_ = std::make_unique<Engine>(std::move(scene), settings_, progress);
  auto first = std::make_shared<SceneSnapshot>();
  first->id = id_;
  first->name = std::move(name);
  first->version = engine_->version();
  first->buildStats = engine_->stats();
  first->scene = engine_->scene();
  for (const Engine::ReceiverChunks& r : engine_->meshChunks(engine_->receiverFaces(), progress)) {
    std::vector<MeshPart> parts = partsOf(first->scene, r, first->version);
    first->parts.insert(first->parts.end(), parts.begin(), parts.end());
  }
  if (progress) progress("occluders", 0, 0);
  first->occluders = std::make_shared<const OccluderIndexes>(freezeOccluders(*engine_, {}, {}).indexes);
  current_ = std::move(first);
}

std::shared_ptr<const SceneSnapshot> SceneSession::snapshot() const {
  std::lock_guard lock(publishMutex_);
  return current_;
}

SceneSession::Applied SceneSession::apply(
    const Frame& frame, const std::function<void(const SceneSnapshot&)>& beforePublish) {
  std::lock_guard edit(editMutex_);
  const std::shared_ptr<const SceneSnapshot> previous = snapshot();
  if (!engine_) rollBackEngine(*previous);  // an earlier rollback failed (no memory?): retry
  try {
    return applyToEngine(frame, previous, beforePublish);
  } catch (const EditError&) {
    throw;  // refused by the check, before anything changed
  } catch (...) {
    // Mid-apply or mid-meshing: the engine is half-edited; nothing was published.
    engine_.reset();  // its memory first
    try {
      rollBackEngine(*previous);
    } catch (...) {
      // engine_ stays null; the next frame tries again. Readers keep `previous`.
    }
    throw;
  }
}

FrameResult SceneSession::applyFrame(Engine& engine, const Frame& frame) {
  FrameResult result = engine.apply(frame);
  engine.compactTrees(result.changedReceivers);
  return result;
}

SceneSession::Applied SceneSession::applyToEngine(
    const Frame& frame, const std::shared_ptr<const SceneSnapshot>& previous,
    const std::function<void(const SceneSnapshot&)>& beforePublish) {
  FrameResult result = applyFrame(*engine_, frame);  // throws EditError before changing anything

  // Build the next whole version beside the published one, then swap it in.
  auto next = std::make_shared<SceneSnapshot>();
  next->id = previous->id;
  next->name = previous->name;
  next->version = result.version;
  next->buildStats = previous->buildStats;
  next->scene = engine_->scene();

  // Only the receivers the frame changed (and new ones) are meshed again, and in them
  // only the chunks that changed; the others keep the previous version's parts, which
  // are what a fresh mesh would give them.
  const auto meshStart = std::chrono::steady_clock::now();
  std::map<ReceiverKey, std::pair<size_t, size_t>> previousRuns;  // receiver → its parts [begin, end)
  for (size_t i = 0; i < previous->parts.size(); ++i) {
    auto [it, added] = previousRuns.try_emplace(previous->parts[i].key.receiver, i, i + 1);
    if (!added) it->second.second = i + 1;
  }
  const std::set<FaceId> changed(result.changedReceivers.begin(), result.changedReceivers.end());
  std::vector<FaceId> remesh;
  std::set<ReceiverKey> redone;  // receivers meshed again or gone: only their parts are compared
  for (const auto& [key, run] : previousRuns) redone.insert(key);
  for (const Engine::Receiver& r : engine_->receivers()) {
    const ReceiverKey key{next->scene.object(r.face.object).id, r.face.face};
    if (changed.count(r.face) || !previousRuns.count(key)) remesh.push_back(r.face);
    else redone.erase(key);  // kept as it was
  }
  const std::vector<Engine::ReceiverChunks> remeshed = engine_->meshChunks(remesh);
  if (settings_.failurePoint) settings_.failurePoint("meshing");
  const Engine::MeshCacheCounters cells = engine_->lastMeshCounters();
  size_t fresh = 0;
  std::vector<size_t> freshParts;  // indices into next->parts of the parts meshed again
  for (const Engine::Receiver& r : engine_->receivers()) {
    if (fresh < remeshed.size() && remeshed[fresh].face == r.face) {
      for (MeshPart& part : partsOf(next->scene, remeshed[fresh++], next->version)) {
        freshParts.push_back(next->parts.size());
        next->parts.push_back(std::move(part));
      }
    } else {
      const auto [begin, end] = previousRuns.at({next->scene.object(r.face.object).id, r.face.face});
      next->parts.insert(next->parts.end(), previous->parts.begin() + long(begin), previous->parts.begin() + long(end));
    }
  }

  // A part's version moves only when its mesh data really changed, so `since` deltas
  // carry what a client must redraw, whatever the engine recomputed; its shape version only
  // when more than its irradiance did, so a light's radiance sends values, not geometry.
  // Receivers kept as they were keep their parts and versions.
  std::map<PartKey, const MeshPart*> before;
  for (const ReceiverKey& key : redone) {
    const auto [begin, end] = previousRuns.at(key);
    for (size_t i = begin; i < end; ++i) before.emplace(previous->parts[i].key, &previous->parts[i]);
  }
  std::vector<MeshPart*> meshedAgain;
  std::set<PartKey> live;  // the parts meshed again: a removed key can only come back among them
  for (size_t i : freshParts) {
    meshedAgain.push_back(&next->parts[i]);
    live.insert(next->parts[i].key);
  }
  const std::vector<PartKey> left = carryPartVersions(std::move(before), meshedAgain);
  const double meshSeconds = secondsSince(meshStart);
  next->removed = previous->removed;
  next->removedFloor = previous->removedFloor;
  recordRemovals(*next, live, left, next->version);

  // Occluder lists for images: the trees of receivers meshed again may have changed.
  FrozenOccluders frozen =
      freezeOccluders(*engine_, *previous->occluders, std::set<FaceId>(remesh.begin(), remesh.end()));
  next->occluders = std::make_shared<const OccluderIndexes>(std::move(frozen.indexes));

  next->lastFrame = result;
  next->frameBase = baseVersion_;
  std::shared_ptr<const SceneSnapshot> published = std::move(next);
  if (beforePublish) beforePublish(*published);  // the journal: a throw undoes the frame
  noteApplied(frame, result, published->scene);
  publish(published);
  return {std::move(result), std::move(published), meshSeconds, remesh.size(), cells, frozen.seconds, frozen.frozen};
}

void SceneSession::replayJournaled(const std::vector<JournaledFrame>& frames,
                                   const SceneToBuild& sceneToBuild,
                                   const EngineProgress& progress) {
  std::lock_guard edit(editMutex_);
  const std::shared_ptr<const SceneSnapshot> start = snapshot();
  if (frames.empty()) return;
  std::map<PartKey, PartVersions> versions;  // every live part's versions, as the frames leave them
  // The bytes of the parts as of `keptAt` (the start, then each fresh build): a part unchanged
  // since keeps them, as it did when served.
  std::map<PartKey, std::shared_ptr<const ReceiverMesh>> kept;
  uint64_t keptAt = start->version;
  for (const MeshPart& part : start->parts) {
    versions[part.key] = {part.version, part.shapeVersion};
    kept[part.key] = part.mesh;
  }
  auto next = std::make_shared<SceneSnapshot>();
  next->removed = start->removed;
  next->removedFloor = start->removedFloor;
  FrameResult last;
  for (const JournaledFrame& journaled : frames) {
    if (progress) progress("replaying", size_t(&journaled - frames.data()), frames.size());
    if (journaled.base && *journaled.base > baseVersion_) {  // served on a fresh build here
      if (*journaled.base != engine_->version())
        throw std::runtime_error("frame " + std::to_string(journaled.version) +
                                 " was applied on a build of version " +
                                 std::to_string(*journaled.base) + ", the replay is at " +
                                 std::to_string(engine_->version()));
      const Scene scene = engine_->scene();
      std::map<PartKey, std::shared_ptr<const ReceiverMesh>> now;
      for (MeshPart& part : meshedParts(versions, kept, keptAt, scene, progress))
        now[part.key] = part.mesh;
      kept = std::move(now);
      keptAt = engine_->version();
      buildBase(sceneToBuild(scene), keptAt, progress);
    }
    last = applyFrame(*engine_, journaled.frame);  // the same trees as when it was served
    if (last.version != journaled.version)
      throw std::runtime_error("replay reached version " + std::to_string(last.version) +
                               ", the journal says " + std::to_string(journaled.version));
    noteApplied(journaled.frame, last, engine_->scene());
    // The frame's journaled part diff: a part that came back is among the changed ones.
    const std::set<PartKey> changed(journaled.changes.changed.begin(), journaled.changes.changed.end());
    for (const PartKey& key : changed) versions[key] = {last.version, last.version};
    for (const PartKey& key : journaled.changes.values) {
      const auto it = versions.find(key);
      if (it == versions.end() || changed.count(key))
        throw std::runtime_error("frame " + std::to_string(journaled.version) +
                                 " journaled new values for a part of receiver '" +
                                 key.receiver.object + "' it does not hold");
      it->second.version = last.version;
    }
    for (const PartKey& key : journaled.changes.removed) versions.erase(key);
    recordRemovals(*next, changed, journaled.changes.removed, last.version);
  }
  next->id = start->id;
  next->name = start->name;
  next->version = last.version;
  next->buildStats = start->buildStats;
  next->scene = engine_->scene();
  next->parts = meshedParts(versions, kept, keptAt, next->scene, progress);
  next->occluders =
      std::make_shared<const OccluderIndexes>(freezeOccluders(*engine_, {}, {}).indexes);
  next->lastFrame = last;
  next->frameBase = frames.back().base.value_or(0);
  publish(std::move(next));
}

std::vector<MeshPart> SceneSession::meshedParts(
    const std::map<PartKey, PartVersions>& versions,
    const std::map<PartKey, std::shared_ptr<const ReceiverMesh>>& kept, uint64_t keptAt,
    const Scene& scene, const EngineProgress& progress) {
  std::vector<MeshPart> parts;
  size_t found = 0;
  for (const Engine::ReceiverChunks& r : engine_->meshChunks(engine_->receiverFaces(), progress))
    for (MeshPart& part : partsOf(scene, r, 0)) {
      const auto it = versions.find(part.key);
      if (it == versions.end())
        throw std::runtime_error("a part of receiver '" + part.key.receiver.object +
                                 "' has no journaled version");
      part.version = it->second.version;
      part.shapeVersion = it->second.shape;
      if (part.version <= keptAt) {
        const auto same = kept.find(part.key);
        if (same == kept.end())
          throw std::runtime_error("a part of receiver '" + part.key.receiver.object +
                                   "' is not among those kept at version " +
                                   std::to_string(keptAt));
        part.mesh = same->second;
      }
      ++found;
      parts.push_back(std::move(part));
    }
  if (found != versions.size())
    throw std::runtime_error(std::to_string(versions.size() - found) +
                             " journaled parts are not in the mesh");
  return parts;
}

void SceneSession::rename(const std::string& name, const std::function<void()>& journal) {
  std::lock_guard edit(editMutex_);
  const std::shared_ptr<const SceneSnapshot> now = snapshot();
  auto next = std::make_shared<SceneSnapshot>();  // a copy, but for its mesh cache
  next->id = now->id;
  next->name = name;
  next->version = now->version;
  next->scene = now->scene;
  next->parts = now->parts;
  next->removed = now->removed;
  next->removedFloor = now->removedFloor;
  next->occluders = now->occluders;
  next->buildStats = now->buildStats;
  next->lastFrame = now->lastFrame;
  next->frameBase = now->frameBase;
  if (journal) journal();
  publish(std::move(next));
}

void SceneSession::publish(std::shared_ptr<const SceneSnapshot> next) {
  {
    std::lock_guard lock(publishMutex_);
    current_ = std::move(next);
  }
  published_.notify_all();
}

RebuildReport SceneSession::rebuild(const EngineProgress& progress) {
  std::lock_guard lock(rebuildMutex_);
  const std::shared_ptr<const SceneSnapshot> served = snapshot();
  RebuildReport report;
  report.version = served->version;
  const auto start = std::chrono::steady_clock::now();
  Engine fresh(served->scene, settings_, progress);
  report.buildSeconds = secondsSince(start);
  const auto meshStart = std::chrono::steady_clock::now();
  const Mesh mesh = fresh.mesh(progress);
  report.meshSeconds = secondsSince(meshStart);
  report.stats = fresh.stats();
  report.meshVertices = mesh.vertexCount();
  report.meshTriangles = mesh.triangleCount();
  report.servedVertices = served->vertexCount();
  report.servedTriangles = served->triangleCount();
  {
    std::lock_guard published(publishMutex_);
    lastRebuild_ = report;
  }
  return report;
}

std::optional<RebuildReport> SceneSession::lastRebuild() const {
  std::lock_guard lock(publishMutex_);
  return lastRebuild_;
}

std::shared_ptr<const SceneSnapshot> SceneSession::waitForVersionAfter(
    uint64_t after, std::chrono::milliseconds timeout) const {
  std::unique_lock lock(publishMutex_);
  published_.wait_for(lock, timeout, [&] { return closed_ || current_->version > after; });
  return current_;
}

void SceneSession::close() {
  {
    std::lock_guard lock(publishMutex_);
    closed_ = true;
  }
  published_.notify_all();
}

bool SceneSession::closed() const {
  std::lock_guard lock(publishMutex_);
  return closed_;
}

}  // namespace penumbra::server
