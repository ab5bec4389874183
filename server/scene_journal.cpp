#include "server/scene_journal.h"

#include <zlib.h>

#include <cstdio>
#include <ctime>
#include <filesystem>

#include "server/data_directory.h"
#include "server/sqlite_db.h"
#include "server/wal_check.h"

namespace penumbra::server {

namespace {

// Frames are keyed by (scene, version); deleting a scene deletes its frames (foreign key).
// `parts` (PartChanges, part_changes.h), `base` (StoredFrame::base), snapshots and the checksums
// `crc` (version and frame), `parts_crc` and `source_crc` came later: NULL in older journals' rows
// (read as intact).
constexpr const char* kSchema = R"(
CREATE TABLE IF NOT EXISTS scenes (
  key INTEGER PRIMARY KEY AUTOINCREMENT,
  id TEXT NOT NULL,
  name TEXT NOT NULL,
  base_version INTEGER NOT NULL,
  source BLOB NOT NULL,
  source_crc INTEGER);
CREATE TABLE IF NOT EXISTS frames (
  scene INTEGER NOT NULL REFERENCES scenes(key) ON DELETE CASCADE,
  version INTEGER NOT NULL,
  frame BLOB NOT NULL,
  parts BLOB,
  crc INTEGER,
  parts_crc INTEGER,
  base INTEGER,
  PRIMARY KEY (scene, version)) WITHOUT ROWID;
CREATE TABLE IF NOT EXISTS snapshots (
  scene INTEGER NOT NULL REFERENCES scenes(key) ON DELETE CASCADE,
  version INTEGER NOT NULL,
  source BLOB NOT NULL,
  parts BLOB NOT NULL,
  crc INTEGER NOT NULL,
  PRIMARY KEY (scene, version)) WITHOUT ROWID;
)";

uint32_t crcOf(uint32_t crc, const std::string& bytes) {
  return uint32_t(crc32(crc, reinterpret_cast<const Bytef*>(bytes.data()), uInt(bytes.size())));
}

// Adds `column` to `table` when a journal from before it lacks it.
void addColumnIfMissing(SqliteDb& db, const std::string& table, const std::string& column,
                        const std::string& type) {
  if (db.queryText("SELECT COUNT(*) FROM pragma_table_info('" + table + "') WHERE name = '" +
                   column + "'") == "0")
    db.exec("ALTER TABLE " + table + " ADD COLUMN " + column + " " + type);
}

// A stored checksum (NULL: none, the row is from before checksums) against the recomputed one.
bool matches(const SqliteStatement& row, int column, uint32_t computed) {
  return row.columnIsNull(column) || uint32_t(row.columnInt(column)) == computed;
}

}  // namespace

uint32_t SceneJournal::frameChecksum(uint64_t version, const std::string& frame) {
  return crcOf(crcOf(0, std::to_string(version)), frame);
}

uint32_t SceneJournal::snapshotChecksum(uint64_t version, const std::string& source,
                                        const std::string& parts) {
  return crcOf(crcOf(crcOf(0, std::to_string(version)), source), parts);
}

SceneJournal::SceneJournal(const std::string& dir) : dir_(std::make_unique<DataDirectory>(dir)) {
  path_ = (std::filesystem::path(dir_->path()) / "journal.sqlite3").string();
  try {
    open();
  } catch (const SqliteError& error) {  // loud, and nothing in the file is changed or dropped
    throw std::runtime_error("the journal '" + path_ + "' cannot be opened (" + error.what() +
                             "): it is damaged. Nothing was changed; keep a copy, then repair it "
                             "(sqlite3 journal.sqlite3 .recover) or move it aside to start empty");
  }
  dir_->watch(path_);
}

// Damage SQLite would pass over in silence (wal_check.h): said, and the log copied aside before
// SQLite opens it (its next write may reuse the file).
std::string SceneJournal::checkWriteAheadLog() const {
  const std::string wal = path_ + "-wal";
  const std::string problem = walProblem(wal);
  if (problem.empty()) return "";
  const std::string copy = wal + ".damaged-" + std::to_string(std::time(nullptr));
  std::error_code error;
  std::filesystem::copy_file(wal, copy, std::filesystem::copy_options::overwrite_existing, error);
  return problem + (error ? "" : "; the log as found is kept as " + copy);
}

void SceneJournal::open() {
  const std::string walDamage = checkWriteAheadLog();
  logDamage_ = walDamage;
  db_ = std::make_unique<SqliteDb>(path_);
  // WAL: a commit appends to the log; synchronous=FULL fsyncs the log at every commit, so an
  // acknowledged frame survives a power loss too, not only a killed process (NORMAL would).
  if (db_->queryText("PRAGMA journal_mode=WAL") != "wal")
    throw std::runtime_error(path_ + ": cannot switch to WAL mode");
  db_->exec("PRAGMA synchronous=FULL; PRAGMA foreign_keys=ON;");
  db_->setBusyTimeout(2000);  // another process holding the file: wait, then fail the write
  // Damage is loud, never silent: what quick_check finds goes to the log and /api/health.
  try {
    integrity_ = db_->queryText("PRAGMA quick_check");
  } catch (const std::exception& error) {
    integrity_ = error.what();
  }
  if (!walDamage.empty())
    integrity_ = integrity_ == "ok" ? walDamage : walDamage + "; " + integrity_;
  if (integrity_ != "ok")
    std::fprintf(stderr, "penumbra serve: the journal %s is damaged: %s\n", path_.c_str(),
                 integrity_.c_str());
  db_->exec(kSchema);
  addColumnIfMissing(*db_, "frames", "parts", "BLOB");  // journals from before each column
  addColumnIfMissing(*db_, "frames", "crc", "INTEGER");
  addColumnIfMissing(*db_, "frames", "parts_crc", "INTEGER");
  addColumnIfMissing(*db_, "scenes", "source_crc", "INTEGER");
  addColumnIfMissing(*db_, "frames", "base", "INTEGER");
}

SceneJournal::~SceneJournal() = default;

const std::string& SceneJournal::directory() const { return dir_->path(); }

std::string SceneJournal::durabilityProblem() const { return dir_->problem(); }

void SceneJournal::requireDurable() const {
  const std::string problem = dir_->problem();
  if (!problem.empty()) throw std::runtime_error(problem);
}

std::vector<SceneJournal::StoredScene> SceneJournal::load() {
  std::lock_guard lock(mutex_);
  std::vector<StoredScene> scenes;
  std::map<int64_t, size_t> index;
  size_t reading = 0;  // the scene whose frames are being read
  try {
    SqliteStatement sceneRows = db_->prepare(
        "SELECT key, id, name, base_version, source, source_crc FROM scenes ORDER BY key");
    while (sceneRows.step()) {
      StoredScene scene;
      scene.key = sceneRows.columnInt(0);
      scene.id = sceneRows.columnBytes(1);
      scene.name = sceneRows.columnBytes(2);
      scene.baseVersion = uint64_t(sceneRows.columnInt(3));
      scene.source = sceneRows.columnBytes(4);
      scene.sourceIntact = matches(sceneRows, 5, crcOf(0, scene.source));
      index[scene.key] = scenes.size();
      lastVersion_[scene.key] = scene.baseVersion;
      scenes.push_back(std::move(scene));
    }
    SqliteStatement frameRows = db_->prepare(
        "SELECT scene, version, frame, parts, crc, parts_crc, base FROM frames ORDER BY scene, "
        "version");
    while (frameRows.step()) {
      const auto it = index.find(frameRows.columnInt(0));
      if (it == index.end()) continue;
      reading = it->second;
      StoredScene& scene = scenes[it->second];
      StoredScene::StoredFrame frame{uint64_t(frameRows.columnInt(1)), frameRows.columnBytes(2),
                                     frameRows.columnBytes(3)};
      frame.intact = matches(frameRows, 4, frameChecksum(frame.version, frame.frame));
      // Damaged part changes only cost speed: that scene replays frame by frame.
      if (!matches(frameRows, 5, crcOf(0, frame.parts))) frame.parts.clear();
      if (!frameRows.columnIsNull(6)) frame.base = uint64_t(frameRows.columnInt(6));
      lastVersion_[scene.key] = frame.version;
      scene.frames.push_back(std::move(frame));
    }
    SqliteStatement snapshotRows = db_->prepare(
        "SELECT scene, version, source, parts, crc FROM snapshots ORDER BY scene, version");
    while (snapshotRows.step()) {
      const auto it = index.find(snapshotRows.columnInt(0));
      if (it == index.end()) continue;
      StoredScene::StoredSnapshot snapshot{uint64_t(snapshotRows.columnInt(1)),
                                           snapshotRows.columnBytes(2),
                                           snapshotRows.columnBytes(3)};
      snapshot.intact = uint32_t(snapshotRows.columnInt(4)) ==
                        snapshotChecksum(snapshot.version, snapshot.source, snapshot.parts);
      scenes[it->second].snapshots.push_back(std::move(snapshot));
    }
  } catch (const std::exception& error) {
    // A damaged file: keep what was read, say so; the scenes from the one being read on may be
    // missing frames, so they take no edits (a new frame would overwrite a kept one).
    loadProblem_ = std::string("reading the journal failed: ") + error.what();
    std::fprintf(stderr, "penumbra serve: %s (%s)\n", loadProblem_.c_str(), path_.c_str());
    for (size_t s = reading; s < scenes.size(); ++s) scenes[s].complete = false;
  }
  return scenes;
}

int64_t SceneJournal::addScene(const std::string& id, const std::string& name,
                               const std::string& source, uint64_t baseVersion) {
  std::lock_guard lock(mutex_);
  requireDurable();
  SqliteTransaction transaction(*db_);
  db_->prepare(
         "INSERT INTO scenes (id, name, base_version, source, source_crc) VALUES (?, ?, ?, ?, ?)")
      .bindText(1, id)
      .bindText(2, name)
      .bind(3, int64_t(baseVersion))
      .bindBlob(4, source)
      .bind(5, int64_t(crcOf(0, source)))
      .run();
  const int64_t key = sqlite3_last_insert_rowid(db_->handle());
  transaction.commit();
  lastVersion_[key] = baseVersion;
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
  SqliteTransaction transaction(*db_);
  db_->prepare(
         "INSERT INTO frames (scene, version, frame, parts, crc, parts_crc, base) VALUES (?, ?, ?, "
         "?, ?, ?, ?)")
      .bind(1, key)
      .bind(2, int64_t(version))
      .bindBlob(3, frame)
      .bindBlob(4, parts)
      .bind(5, int64_t(frameChecksum(version, frame)))
      .bind(6, int64_t(crcOf(0, parts)))
      .bind(7, int64_t(base))
      .run();
  transaction.commit();
  last->second = version;
}

void SceneJournal::addSnapshot(int64_t key, uint64_t version, const std::string& source,
                               const std::string& parts) {
  std::lock_guard lock(mutex_);
  if (!lastVersion_.count(key)) throw std::runtime_error("the scene is no longer journaled");
  requireDurable();
  SqliteTransaction transaction(*db_);
  db_->prepare(
         "INSERT OR REPLACE INTO snapshots (scene, version, source, parts, crc) VALUES (?, ?, "
         "?, ?, ?)")
      .bind(1, key)
      .bind(2, int64_t(version))
      .bindBlob(3, source)
      .bindBlob(4, parts)
      .bind(5, int64_t(snapshotChecksum(version, source, parts)))
      .run();
  // Older snapshots only cost space: a restart starts from the newest that verifies.
  db_->prepare(
         "DELETE FROM snapshots WHERE scene = ? AND version NOT IN (SELECT version FROM "
         "snapshots WHERE scene = ? ORDER BY version DESC LIMIT ?)")
      .bind(1, key)
      .bind(2, key)
      .bind(3, int64_t(kSnapshotsKept))
      .run();
  transaction.commit();
}

void SceneJournal::removeScene(int64_t key) {
  std::lock_guard lock(mutex_);
  requireDurable();
  SqliteTransaction transaction(*db_);
  db_->prepare("DELETE FROM scenes WHERE key = ?").bind(1, key).run();
  transaction.commit();
  lastVersion_.erase(key);
}

}  // namespace penumbra::server
