// SceneSession's fresh builds at snapshot points (docs/SERVER.md "Snapshots"): rebase() while
// serving, adoptSnapshot() at a restart, and the base they and rollBackEngine share.
#include <set>
#include <stdexcept>

#include "server/scene_session.h"

namespace penumbra::server {

void SceneSession::buildBase(Scene scene, uint64_t version, const EngineProgress& progress) {
  auto engine = std::make_unique<Engine>(scene, settings_, progress);  // may throw: nothing changed yet
  engine->setVersion(version);
  baseScene_ = std::move(scene);
  baseVersion_ = version;
  sinceBase_.clear();
  replayable_ = true;
  engine_ = std::move(engine);
}

std::shared_ptr<const SceneSnapshot> SceneSession::rebase(const SceneToBuild& sceneToBuild,
                                                          const EngineProgress& progress) {
  std::lock_guard edit(editMutex_);
  std::shared_ptr<const SceneSnapshot> published = snapshot();
  buildBase(sceneToBuild(published->scene), published->version, progress);
  return published;
}

uint64_t SceneSession::engineBase() {
  std::lock_guard edit(editMutex_);
  return baseVersion_;
}

void SceneSession::adoptSnapshot(uint64_t version, StoredParts stored) {
  std::lock_guard edit(editMutex_);
  const std::shared_ptr<const SceneSnapshot> built = snapshot();
  // The stored parts must be the built scene's (their bytes may differ in the last bits: the
  // stored ones are those served; their order too is the one served).
  std::set<PartKey> builtKeys, storedKeys;
  for (const MeshPart& part : built->parts) builtKeys.insert(part.key);
  for (const MeshPart& part : stored.parts) {
    if (part.version > version) throw std::runtime_error("a part is newer than the snapshot");
    storedKeys.insert(part.key);
  }
  if (storedKeys != builtKeys || storedKeys.size() != stored.parts.size())
    throw std::runtime_error("its mesh parts are not those of its scene's receivers");
  auto next = std::make_shared<SceneSnapshot>();
  next->id = built->id;
  next->name = built->name;
  next->version = version;
  next->scene = built->scene;
  next->buildStats = built->buildStats;
  next->occluders = built->occluders;
  next->parts = std::move(stored.parts);
  next->removed = std::move(stored.removed);
  next->removedFloor = stored.removedFloor;
  next->frameBase = version;
  engine_->setVersion(version);
  baseVersion_ = version;
  publish(std::move(next));
}

}  // namespace penumbra::server
