// One served scene: its engine (edits applied one frame at a time under a writer mutex) and
// the latest published immutable SceneSnapshot, which readers take without waiting.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/engine/engine.h"
#include "server/edit_scheduler.h"
#include "server/indirect_cache.h"
#include "server/limits.h"
#include "server/part_changes.h"
#include "server/scene_snapshot.h"
#include "server/stored_parts.h"

namespace penumbra::server {

// What POST /api/scenes/{id}/rebuild reports: a full build of the current scene
// from scratch (the engine that serves edits is left as it is).
struct RebuildReport {
  uint64_t version = 0;     // the version that was rebuilt
  double buildSeconds = 0;  // Engine construction (ordering .. illumination)
  double meshSeconds = 0;   // triangulation
  BuildStats stats;
  size_t meshVertices = 0, meshTriangles = 0;      // of the rebuilt mesh
  size_t servedVertices = 0, servedTriangles = 0;  // of the served one, for comparison
};

class SceneSession {
 public:
  // Builds the engine (may take seconds for large scenes) and publishes version 0. `progress`
  // sees the engine's steps, the display meshing ("triangulation") and "occluders"; an exception
  // it throws ends the construction (BuildJob's cancel), everything built so far freed.
  SceneSession(std::string id, std::string name, Scene scene, EngineSettings settings = {},
               const EngineProgress& progress = {});

  const std::string& id() const { return id_; }
  // The files of the scene's volumes as it was built (a client's frame may add them back).
  const std::vector<std::string>& initialVolumeFiles() const { return initialVolumeFiles_; }
  std::shared_ptr<const SceneSnapshot> snapshot() const;

  // Applies one frame, serialised with other frames of this scene, and publishes
  // the new version before returning it with the engine's result. Only the receivers
  // the engine reports changed (and new ones) are meshed again. Throws EditError
  // (nothing changed) on an invalid frame. Atomic: on any other exception (no memory, an
  // internal error) the engine is restored to the published version before the exception
  // is rethrown, so the scene, engine and version are exactly as before the call.
  // `beforePublish` (the journal) sees the new version after the engine applied it and
  // before it is published; if it throws, the frame is undone like any other failure.
  struct Applied {
    FrameResult result;
    std::shared_ptr<const SceneSnapshot> snapshot;  // the version this frame made
    double meshSeconds = 0;     // re-meshing the changed receivers and assembling the mesh
    size_t meshedReceivers = 0;  // receivers meshed again (the others kept their mesh)
    Engine::MeshCacheCounters meshCells;  // of those receivers' cells: replayed / lit afresh
    double occluderSeconds = 0;   // freezing the changed microfacet receivers' occluder lists
    size_t occluderReceivers = 0;  // receivers frozen afresh (scene_occluders.h)
  };
  Applied apply(const Frame& frame,
                const std::function<void(const SceneSnapshot&)>& beforePublish = nullptr);

  // At a restart (journal_write_restore.cpp), on a fresh session: applies journaled frames in
  // order to the engine alone, then meshes every receiver once and publishes the last version,
  // each part's version and the removals taken from what the frames journaled. That is what
  // applying them one by one published (same bytes, versions and `since` deltas) at a fraction
  // of the cost: meshing is most of a frame. Throws if a frame does not apply or the changes do
  // not fit the mesh; the session is then unusable (the caller starts again from a fresh one).
  // `progress` sees step "replaying" before each frame, and the builds' and the meshing's steps;
  // what it throws (a restore's cancel) ends the replay the same way.
  // A frame whose `base` is newer than the engine's is applied, as it was served, on a fresh
  // build at that version (rebase(); `sceneToBuild` as given there), and the parts kept from
  // before the build keep their bytes (the fresh engine's agree only to 1e-9).
  struct JournaledFrame {
    Frame frame;
    uint64_t version = 0;
    PartChanges changes;
    std::optional<uint64_t> base;  // SceneJournal's StoredFrame::base
  };
  using SceneToBuild = std::function<Scene(const Scene&)>;
  void replayJournaled(const std::vector<JournaledFrame>& frames, const SceneToBuild& sceneToBuild,
                       const EngineProgress& progress = {});

  // Snapshots (docs/SERVER.md "Snapshots"; scene_session_rebase.cpp). rebase() replaces the
  // engine by a fresh build of `sceneToBuild(published scene)` at the published version — the
  // scene as a journal snapshot records it — publishing nothing: the served parts keep their
  // bytes, the frames after it are applied on the new build (so a restart from the snapshot,
  // the same build then the same frames, gives them back byte for byte). Returns the version
  // rebased at. On failure (no memory, or `progress` throwing: the build's) the engine is left as
  // it was.
  std::shared_ptr<const SceneSnapshot> rebase(const SceneToBuild& sceneToBuild,
                                              const EngineProgress& progress = {});
  // The version whose fresh build the engine came from (SceneSnapshot::frameBase).
  uint64_t engineBase();
  // On a session just built from a snapshot's scene: publishes the snapshot's version with its
  // stored parts (the engine numbered to match). Throws std::runtime_error, changing nothing,
  // when the parts do not match the scene's receivers.
  void adoptSnapshot(uint64_t version, StoredParts stored);

  // A full rebuild of the current version, timed. Serialised with other rebuilds,
  // not with edits (it works on a snapshot's scene). `progress` is the engine's: what it throws
  // ends the rebuild (a cancel), nothing recorded.
  RebuildReport rebuild(const EngineProgress& progress = {});
  std::optional<RebuildReport> lastRebuild() const;

  // Waits until a version newer than `after` is published, the session is closed,
  // or the timeout passes; returns the current snapshot.
  std::shared_ptr<const SceneSnapshot> waitForVersionAfter(uint64_t after,
                                                           std::chrono::milliseconds timeout) const;

  // The scene's edit queue: callers of apply() take a turn here first (edit_routes.cpp),
  // so waiting frames are bounded and clients take turns.
  EditScheduler& editQueue() { return editQueue_; }

  // Indirect light baked per version on first request (mesh?indirect=1); independent of edits.
  IndirectCache& indirectCache() const { return indirect_; }

  // Publishes the current version again under a new name, serialised with frames: `journal`
  // (which may throw, changing nothing) sees it first. The version does not move.
  void rename(const std::string& name, const std::function<void()>& journal);

  // Marks the session deleted: waiters wake, event streams end.
  void close();
  bool closed() const;

 private:
  void publish(std::shared_ptr<const SceneSnapshot> next);
  Applied applyToEngine(const Frame& frame, const std::shared_ptr<const SceneSnapshot>& previous,
                        const std::function<void(const SceneSnapshot&)>& beforePublish);
  // One frame as every path applies it to an engine (serving, the journal's replay, the
  // rollback's), so their trees come out the same: Engine::apply, then the trees it changed
  // cast afresh where dead slots dominate (bounded memory; those receivers are meshed again).
  static FrameResult applyFrame(Engine& engine, const Frame& frame);
  // Failure path of apply, the engine rollback (scene_session_rollback.cpp), with editMutex_
  // held: replaces engine_ by one equal to the engine that made `published` (or leaves it null
  // and throws).
  void rollBackEngine(const SceneSnapshot& published);
  void noteApplied(const Frame& frame, const FrameResult& result, const Scene& scene);
  // With editMutex_ held: engine_ becomes a fresh build of `scene` numbered `version`, the new
  // base (rebase(), rollBackEngine's fallback).
  void buildBase(Scene scene, uint64_t version, const EngineProgress& progress = {});
  struct PartVersions {
    uint64_t version = 0, shape = 0;  // MeshPart::version, MeshPart::shapeVersion
  };
  // With editMutex_ held: the engine's mesh as parts, each at its versions in `versions` (every
  // part must be there, and only those); a part at or before `keptAt` has the bytes in `kept`.
  std::vector<MeshPart> meshedParts(
      const std::map<PartKey, PartVersions>& versions,
      const std::map<PartKey, std::shared_ptr<const ReceiverMesh>>& kept, uint64_t keptAt,
      const Scene& scene, const EngineProgress& progress = {});

  const std::string id_;
  const EngineSettings settings_;
  std::vector<std::string> initialVolumeFiles_;
  EditScheduler editQueue_{kMaxQueuedEdits, kMaxFramesPerBatch};
  std::mutex editMutex_;  // one frame at a time; guards engine_
  std::unique_ptr<Engine> engine_;  // null after a restore that failed: rebuilt on the next frame
  // How to rebuild engine_ exactly (guarded by editMutex_; the engine is deterministic): a
  // fresh build of baseScene_ numbered baseVersion_, then the frames applied since, replayed.
  // Past kMaxReplayFrames the log is dropped and a restore rebuilds the published scene.
  Scene baseScene_;
  uint64_t baseVersion_ = 0;
  std::vector<Frame> sinceBase_;
  bool replayable_ = true;
  mutable std::mutex rebuildMutex_;  // one rebuild at a time

  mutable std::mutex publishMutex_;  // guards current_, closed_, lastRebuild_
  mutable std::condition_variable published_;
  std::shared_ptr<const SceneSnapshot> current_;
  std::optional<RebuildReport> lastRebuild_;
  bool closed_ = false;
  mutable IndirectCache indirect_{kIndirectCacheEntries};
};

}  // namespace penumbra::server
