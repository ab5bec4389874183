#include "server/scene_journal.h"

#include <filesystem>

#include "server/sqlite_db.h"

namespace penumbra::server {

namespace {

// Frames are keyed by (scene, version); deleting a scene deletes its frames (foreign key).
// `parts` (PartChanges, part_changes.h) came later: NULL in older journals' rows.
constexpr const char* kSchema = R"(
CREATE TABLE IF NOT EXISTS scenes (
  key INTEGER PRIMARY KEY AUTOINCREMENT,
  id TEXT NOT NULL,
  name TEXT NOT NULL,
  base_version INTEGER NOT NULL,
  source BLOB NOT NULL);
CREATE TABLE IF NOT EXISTS frames (
  scene INTEGER NOT NULL REFERENCES scenes(key) ON DELETE CASCADE,
  version INTEGER NOT NULL,
  frame BLOB NOT NULL,
  parts BLOB,
  PRIMARY KEY (scene, version)) WITHOUT ROWID;
)";

}  // namespace

SceneJournal::SceneJournal(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code error;
  fs::create_directories(dir, error);
  if (!fs::is_directory(dir)) throw std::runtime_error("--data: cannot create directory '" + dir + "'");
  path_ = (fs::path(dir) / "journal.sqlite3").string();
  db_ = std::make_unique<SqliteDb>(path_);
  // WAL: a commit appends to the log; synchronous=FULL fsyncs the log at every commit, so an
  // acknowledged frame survives a power loss too, not only a killed process (NORMAL would).
  if (db_->queryText("PRAGMA journal_mode=WAL") != "wal")
    throw std::runtime_error(path_ + ": cannot switch to WAL mode");
  db_->exec("PRAGMA synchronous=FULL; PRAGMA foreign_keys=ON;");
  db_->setBusyTimeout(2000);  // another process holding the file: wait, then fail the write
  db_->exec(kSchema);
  if (db_->queryText("SELECT COUNT(*) FROM pragma_table_info('frames') WHERE name = 'parts'") == "0")
    db_->exec("ALTER TABLE frames ADD COLUMN parts BLOB");  // a journal from before the column
}

SceneJournal::~SceneJournal() = default;

std::vector<SceneJournal::StoredScene> SceneJournal::load() {
  std::lock_guard lock(mutex_);
  std::vector<StoredScene> scenes;
  std::map<int64_t, size_t> index;
  SqliteStatement sceneRows =
      db_->prepare("SELECT key, id, name, base_version, source FROM scenes ORDER BY key");
  while (sceneRows.step()) {
    StoredScene scene;
    scene.key = sceneRows.columnInt(0);
    scene.id = sceneRows.columnBytes(1);
    scene.name = sceneRows.columnBytes(2);
    scene.baseVersion = uint64_t(sceneRows.columnInt(3));
    scene.source = sceneRows.columnBytes(4);
    index[scene.key] = scenes.size();
    lastVersion_[scene.key] = scene.baseVersion;
    scenes.push_back(std::move(scene));
  }
  SqliteStatement frameRows =
      db_->prepare("SELECT scene, version, frame, parts FROM frames ORDER BY scene, version");
  while (frameRows.step()) {
    const auto it = index.find(frameRows.columnInt(0));
    if (it == index.end()) continue;
    StoredScene& scene = scenes[it->second];
    const uint64_t version = uint64_t(frameRows.columnInt(1));
    scene.frames.push_back({version, frameRows.columnBytes(2), frameRows.columnBytes(3)});
    lastVersion_[scene.key] = version;
  }
  return scenes;
}

int64_t SceneJournal::addScene(const std::string& id, const std::string& name,
                               const std::string& source, uint64_t baseVersion) {
  std::lock_guard lock(mutex_);
  SqliteTransaction transaction(*db_);
  db_->prepare("INSERT INTO scenes (id, name, base_version, source) VALUES (?, ?, ?, ?)")
      .bindText(1, id)
      .bindText(2, name)
      .bind(3, int64_t(baseVersion))
      .bindBlob(4, source)
      .run();
  const int64_t key = sqlite3_last_insert_rowid(db_->handle());
  transaction.commit();
  lastVersion_[key] = baseVersion;
  return key;
}

void SceneJournal::addFrame(int64_t key, uint64_t version, const std::string& frame,
                            const std::string& parts) {
  std::lock_guard lock(mutex_);
  const auto last = lastVersion_.find(key);
  if (last == lastVersion_.end()) throw std::runtime_error("the scene is no longer journaled");
  if (version != last->second + 1)
    throw std::runtime_error("version " + std::to_string(version) + " does not follow the last " +
                             "journaled version " + std::to_string(last->second) +
                             " (an earlier frame could not be journaled)");
  SqliteTransaction transaction(*db_);
  db_->prepare("INSERT INTO frames (scene, version, frame, parts) VALUES (?, ?, ?, ?)")
      .bind(1, key)
      .bind(2, int64_t(version))
      .bindBlob(3, frame)
      .bindBlob(4, parts)
      .run();
  transaction.commit();
  last->second = version;
}

void SceneJournal::removeScene(int64_t key) {
  std::lock_guard lock(mutex_);
  SqliteTransaction transaction(*db_);
  db_->prepare("DELETE FROM scenes WHERE key = ?").bind(1, key).run();
  transaction.commit();
  lastVersion_.erase(key);
}

void SceneJournal::truncateAfter(int64_t key, uint64_t version) {
  std::lock_guard lock(mutex_);
  SqliteTransaction transaction(*db_);
  db_->prepare("DELETE FROM frames WHERE scene = ? AND version > ?")
      .bind(1, key)
      .bind(2, int64_t(version))
      .run();
  transaction.commit();
  lastVersion_[key] = version;
}

}  // namespace penumbra::server
