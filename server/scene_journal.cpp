#include "server/scene_journal.h"

#include <zlib.h>

#include <cstdio>

#include "server/data_directory.h"
#include "server/journal_store.h"
#include "server/journal_unavailable.h"
#include "server/postgres_journal_store.h"
#include "server/sqlite_journal_store.h"

namespace penumbra::server {

namespace {

uint32_t crcOf(uint32_t crc, const std::string& bytes) {
  return uint32_t(crc32(crc, reinterpret_cast<const Bytef*>(bytes.data()), uInt(bytes.size())));
}

// A stored checksum (none: the row is from before checksums) against the recomputed one.
bool matches(std::optional<int64_t> stored, uint32_t computed) {
  return !stored || uint32_t(*stored) == computed;
}

std::unique_ptr<JournalStore> openStore(DataDirectory& dir, const std::string& database) {
  if (database.empty()) return std::make_unique<SqliteJournalStore>(dir);
  return std::make_unique<PostgresJournalStore>(database);
}

}  // namespace

uint32_t SceneJournal::frameChecksum(uint64_t version, const std::string& frame) {
  return crcOf(crcOf(0, std::to_string(version)), frame);
}

uint32_t SceneJournal::snapshotChecksum(uint64_t version, const std::string& source,
                                        const std::string& parts) {
  return crcOf(crcOf(crcOf(0, std::to_string(version)), source), parts);
}

SceneJournal::SceneJournal(const std::string& dir, const std::string& database)
    : dir_(std::make_unique<DataDirectory>(dir)), store_(openStore(*dir_, database)) {}

SceneJournal::~SceneJournal() = default;

const std::string& SceneJournal::path() const { return store_->where(); }
const std::string& SceneJournal::integrity() const { return store_->integrity(); }
const std::string& SceneJournal::logDamage() const { return store_->logDamage(); }
const std::string& SceneJournal::directory() const { return dir_->path(); }

std::string SceneJournal::durabilityProblem() const {
  if (std::string problem = dir_->problem(); !problem.empty()) return problem;
  // A write in flight answers for itself (its failure is a 503): health does not wait behind it.
  std::unique_lock lock(mutex_, std::try_to_lock);
  return lock.owns_lock() ? store_->problem(true) : "";
}

void SceneJournal::requireDurable() const {
  std::string problem = dir_->problem();
  if (problem.empty()) problem = store_->problem(false);
  if (!problem.empty()) throw JournalUnavailable(problem);
}

void SceneJournal::requireReachable() const {
  if (const std::string problem = store_->problem(false); !problem.empty())
    throw JournalUnavailable(problem);
}

namespace {

SceneJournal::StoredScene storedScene(JournalSceneRow&& row) {
  SceneJournal::StoredScene scene;
  scene.key = row.key;
  scene.id = std::move(row.id);
  scene.name = std::move(row.name);
  scene.baseVersion = uint64_t(row.baseVersion);
  scene.source = std::move(row.source);
  scene.sourceIntact = matches(row.sourceCrc, crcOf(0, scene.source));
  return scene;
}

SceneJournal::StoredScene::StoredFrame storedFrame(JournalFrameRow&& row) {
  SceneJournal::StoredScene::StoredFrame frame;
  frame.version = uint64_t(row.version);
  frame.frame = std::move(row.frame);
  frame.parts = std::move(row.parts);
  frame.intact = matches(row.crc, SceneJournal::frameChecksum(frame.version, frame.frame));
  // Damaged part changes only cost speed: that scene replays frame by frame.
  if (!matches(row.partsCrc, crcOf(0, frame.parts))) frame.parts.clear();
  if (row.base) frame.base = uint64_t(*row.base);
  return frame;
}

SceneJournal::StoredScene::StoredSnapshot storedSnapshot(JournalSnapshotRow&& row) {
  SceneJournal::StoredScene::StoredSnapshot snapshot{uint64_t(row.version), std::move(row.source),
                                                     std::move(row.parts)};
  snapshot.intact = uint32_t(row.crc) == SceneJournal::snapshotChecksum(
                                             snapshot.version, snapshot.source, snapshot.parts);
  return snapshot;
}

}  // namespace

std::vector<SceneJournal::StoredScene> SceneJournal::load() {
  std::lock_guard lock(mutex_);
  std::vector<StoredScene> scenes;
  std::map<int64_t, size_t> index;
  size_t reading = 0;  // the scene whose frames are being read
  try {
    store_->readScenes([&](JournalSceneRow&& row) {
      StoredScene scene = storedScene(std::move(row));
      index[scene.key] = scenes.size();
      lastVersion_[scene.key] = scene.baseVersion;
      scenes.push_back(std::move(scene));
    });
    store_->readFrames([&](JournalFrameRow&& row) {
      const auto it = index.find(row.scene);
      if (it == index.end()) return;
      reading = it->second;
      StoredScene& scene = scenes[it->second];
      lastVersion_[scene.key] = uint64_t(row.version);
      scene.frames.push_back(storedFrame(std::move(row)));
    });
    store_->readSnapshots([&](JournalSnapshotRow&& row) {
      const auto it = index.find(row.scene);
      if (it == index.end()) return;
      scenes[it->second].snapshots.push_back(storedSnapshot(std::move(row)));
    });
  } catch (const std::exception& error) {
    // A damaged file: keep what was read, say so; the scenes from the one being read on may be
    // missing frames, so they take no edits (a new frame would overwrite a kept one).
    loadProblem_ = std::string("reading the journal failed: ") + error.what();
    std::fprintf(stderr, "penumbra serve: %s (%s)\n", loadProblem_.c_str(),
                 store_->where().c_str());
    for (size_t s = reading; s < scenes.size(); ++s) scenes[s].complete = false;
  }
  return scenes;
}

std::optional<SceneJournal::StoredScene> SceneJournal::loadScene(const std::string& id,
                                                                 int64_t lease) {
  std::lock_guard lock(mutex_);
  requireReachable();
  std::optional<JournalSceneRow> row = store_->sceneById(id);
  if (!row) return std::nullopt;
  StoredScene scene = storedScene(std::move(*row));
  uint64_t last = scene.baseVersion;
  try {
    store_->readFramesOf(scene.key, [&](JournalFrameRow&& frame) {
      last = uint64_t(frame.version);
      scene.frames.push_back(storedFrame(std::move(frame)));
    });
    store_->readSnapshotsOf(scene.key, [&](JournalSnapshotRow&& snapshot) {
      scene.snapshots.push_back(storedSnapshot(std::move(snapshot)));
    });
  } catch (const std::exception& error) {
    std::fprintf(stderr, "penumbra serve: reading scene '%s' from the journal failed: %s\n",
                 id.c_str(), error.what());
    scene.complete = false;
  }
  lastVersion_[scene.key] = last;
  leases_[scene.key] = lease;
  return scene;
}

bool SceneJournal::hasScene(const std::string& id) {
  std::lock_guard lock(mutex_);
  requireReachable();
  return store_->sceneById(id).has_value();
}

void SceneJournal::holdLease(int64_t key, int64_t lease) {
  std::lock_guard lock(mutex_);
  leases_[key] = lease;
}

void SceneJournal::forgetScene(int64_t key) {
  std::lock_guard lock(mutex_);
  lastVersion_.erase(key);
  leases_.erase(key);
}

LeaseToken SceneJournal::leaseOf(int64_t key) const {
  const auto it = leases_.find(key);
  return it == leases_.end() ? LeaseToken() : LeaseToken(it->second);
}

int64_t SceneJournal::addScene(const std::string& id, const std::string& name,
                               const std::string& source, uint64_t baseVersion, LeaseToken lease) {
  std::lock_guard lock(mutex_);
  requireDurable();
  const int64_t key = store_->insertScene(
      {0, id, name, int64_t(baseVersion), source, int64_t(crcOf(0, source))}, lease);
  lastVersion_[key] = baseVersion;
  if (lease) leases_[key] = *lease;
  return key;
}

void SceneJournal::addFrame(int64_t key, uint64_t version, const std::string& frame,
                            const std::string& parts, uint64_t base) {
  std::lock_guard lock(mutex_);
  const auto last = lastVersion_.find(key);
  if (last == lastVersion_.end()) throw std::runtime_error("the scene is no longer journaled");
  if (version != last->second + 1)
    throw std::runtime_error("version " + std::to_string(version) + " does not follow the last " +
                             "journaled version " + std::to_string(last->second) +
                             " (an earlier frame could not be journaled)");
  requireDurable();
  store_->insertFrame({key, int64_t(version), frame, parts, int64_t(frameChecksum(version, frame)),
                       int64_t(crcOf(0, parts)), int64_t(base)},
                      leaseOf(key));
  last->second = version;
}

void SceneJournal::addSnapshot(int64_t key, uint64_t version, const std::string& source,
                               const std::string& parts) {
  std::lock_guard lock(mutex_);
  if (!lastVersion_.count(key)) throw std::runtime_error("the scene is no longer journaled");
  requireDurable();
  // Older snapshots only cost space: a restart starts from the newest that verifies.
  store_->putSnapshot(
      {key, int64_t(version), source, parts, int64_t(snapshotChecksum(version, source, parts))},
      kSnapshotsKept, leaseOf(key));
}

void SceneJournal::removeScene(int64_t key) {
  std::lock_guard lock(mutex_);
  requireDurable();
  store_->deleteScene(key, leaseOf(key));
  lastVersion_.erase(key);
  leases_.erase(key);
}

void SceneJournal::renameScene(int64_t key, const std::string& name) {
  std::lock_guard lock(mutex_);
  requireDurable();
  store_->renameScene(key, name, leaseOf(key));
}

}  // namespace penumbra::server
