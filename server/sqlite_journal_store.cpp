#include "server/sqlite_journal_store.h"

#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "server/data_directory.h"
#include "server/sqlite_db.h"
#include "server/wal_check.h"

namespace penumbra::server {

namespace {

// Frames are keyed by (scene, version); deleting a scene deletes its frames (foreign key).
// `parts` (PartChanges, part_changes.h), `base` (StoredFrame::base), snapshots and the checksums
// `crc` (version and frame), `parts_crc` and `source_crc` came later: NULL in older journals' rows
// (read as intact). An uploaded volume is a `volumes` row (its size and CRC) and its bytes in the
// data directory under its name, as uploads were kept before the rows (older journals' uploads
// have no row, and stay where they are).
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
CREATE TABLE IF NOT EXISTS volumes (
  scene INTEGER NOT NULL REFERENCES scenes(key) ON DELETE CASCADE,
  name TEXT NOT NULL,
  size INTEGER NOT NULL,
  crc INTEGER NOT NULL,
  PRIMARY KEY (scene, name)) WITHOUT ROWID;
)";

// Adds `column` to `table` when a journal from before it lacks it.
void addColumnIfMissing(SqliteDb& db, const std::string& table, const std::string& column,
                        const std::string& type) {
  if (db.queryText("SELECT COUNT(*) FROM pragma_table_info('" + table + "') WHERE name = '" +
                   column + "'") == "0")
    db.exec("ALTER TABLE " + table + " ADD COLUMN " + column + " " + type);
}

std::optional<int64_t> optionalInt(const SqliteStatement& row, int column) {
  if (row.columnIsNull(column)) return std::nullopt;
  return row.columnInt(column);
}

SqliteStatement& bindOptional(SqliteStatement& statement, int index, std::optional<int64_t> value) {
  return value ? statement.bind(index, *value) : statement;  // unbound parameters are NULL
}

}  // namespace

SqliteJournalStore::SqliteJournalStore(DataDirectory& dir)
    : path_((std::filesystem::path(dir.path()) / "journal.sqlite3").string()), dir_(dir.path()) {
  try {
    open();
  } catch (const SqliteUnavailable& error) {  // the file or its directory, not its contents
    throw std::runtime_error("the journal '" + path_ + "' cannot be opened (" + error.what() + ")");
  } catch (const SqliteError& error) {  // loud, and nothing in the file is changed or dropped
    throw std::runtime_error("the journal '" + path_ + "' cannot be opened (" + error.what() +
                             "): it is damaged. Nothing was changed; keep a copy, then repair it "
                             "(sqlite3 journal.sqlite3 .recover) or move it aside to start empty");
  }
  dir.watch(path_);
}

SqliteJournalStore::~SqliteJournalStore() = default;

// Damage SQLite would pass over in silence (wal_check.h): said, and the log copied aside before
// SQLite opens it (its next write may reuse the file).
std::string SqliteJournalStore::checkWriteAheadLog() const {
  const std::string wal = path_ + "-wal";
  const std::string problem = walProblem(wal);
  if (problem.empty()) return "";
  const std::string copy = wal + ".damaged-" + std::to_string(std::time(nullptr));
  std::error_code error;
  std::filesystem::copy_file(wal, copy, std::filesystem::copy_options::overwrite_existing, error);
  return problem + (error ? "" : "; the log as found is kept as " + copy);
}

void SqliteJournalStore::open() {
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

void SqliteJournalStore::readScenes(const std::function<void(JournalSceneRow&&)>& row) {
  SqliteStatement rows = db_->prepare(
      "SELECT key, id, name, base_version, source, source_crc FROM scenes ORDER BY key");
  while (rows.step())
    row({rows.columnInt(0), rows.columnBytes(1), rows.columnBytes(2), rows.columnInt(3),
         rows.columnBytes(4), optionalInt(rows, 5)});
}

void SqliteJournalStore::readFrames(const std::function<void(JournalFrameRow&&)>& row) {
  SqliteStatement rows = db_->prepare(
      "SELECT scene, version, frame, parts, crc, parts_crc, base FROM frames ORDER BY scene, "
      "version");
  while (rows.step())
    row({rows.columnInt(0), rows.columnInt(1), rows.columnBytes(2), rows.columnBytes(3),
         optionalInt(rows, 4), optionalInt(rows, 5), optionalInt(rows, 6)});
}

void SqliteJournalStore::readSnapshots(const std::function<void(JournalSnapshotRow&&)>& row) {
  SqliteStatement rows = db_->prepare(
      "SELECT scene, version, source, parts, crc FROM snapshots ORDER BY scene, version");
  while (rows.step())
    row({rows.columnInt(0), rows.columnInt(1), rows.columnBytes(2), rows.columnBytes(3),
         rows.columnInt(4)});
}

int64_t SqliteJournalStore::insertScene(const JournalSceneRow& scene, LeaseToken) {
  SqliteTransaction transaction(*db_);
  SqliteStatement insert = db_->prepare(
      "INSERT INTO scenes (id, name, base_version, source, source_crc) VALUES (?, ?, ?, ?, ?)");
  insert.bindText(1, scene.id).bindText(2, scene.name).bind(3, scene.baseVersion);
  bindOptional(insert.bindBlob(4, scene.source), 5, scene.sourceCrc).run();
  const int64_t key = sqlite3_last_insert_rowid(db_->handle());
  transaction.commit();
  return key;
}

void SqliteJournalStore::insertFrame(const JournalFrameRow& frame, LeaseToken) {
  SqliteTransaction transaction(*db_);
  SqliteStatement insert = db_->prepare(
      "INSERT INTO frames (scene, version, frame, parts, crc, parts_crc, base) VALUES (?, ?, ?, "
      "?, ?, ?, ?)");
  insert.bind(1, frame.scene)
      .bind(2, frame.version)
      .bindBlob(3, frame.frame)
      .bindBlob(4, frame.parts);
  bindOptional(insert, 5, frame.crc);
  bindOptional(insert, 6, frame.partsCrc);
  bindOptional(insert, 7, frame.base).run();
  transaction.commit();
}

void SqliteJournalStore::putSnapshot(const JournalSnapshotRow& snapshot, size_t keep,
                                     LeaseToken) {
  SqliteTransaction transaction(*db_);
  db_->prepare(
         "INSERT OR REPLACE INTO snapshots (scene, version, source, parts, crc) VALUES (?, ?, "
         "?, ?, ?)")
      .bind(1, snapshot.scene)
      .bind(2, snapshot.version)
      .bindBlob(3, snapshot.source)
      .bindBlob(4, snapshot.parts)
      .bind(5, snapshot.crc)
      .run();
  db_->prepare(
         "DELETE FROM snapshots WHERE scene = ? AND version NOT IN (SELECT version FROM "
         "snapshots WHERE scene = ? ORDER BY version DESC LIMIT ?)")
      .bind(1, snapshot.scene)
      .bind(2, snapshot.scene)
      .bind(3, int64_t(keep))
      .run();
  transaction.commit();
}

void SqliteJournalStore::deleteScene(int64_t key, LeaseToken) {
  const std::vector<JournalVolumeRow> volumes = volumesOf(key);
  SqliteTransaction transaction(*db_);
  db_->prepare("DELETE FROM scenes WHERE key = ?").bind(1, key).run();  // its rows cascade
  transaction.commit();
  std::error_code ignored;  // a file left behind is removed at the next start (orphan_uploads.h)
  for (const JournalVolumeRow& volume : volumes)
    std::filesystem::remove(fileOf(volume.name), ignored);
}

void SqliteJournalStore::renameScene(int64_t key, const std::string& name, LeaseToken) {
  SqliteTransaction transaction(*db_);
  db_->prepare("UPDATE scenes SET name = ? WHERE key = ?").bindText(1, name).bind(2, key).run();
  transaction.commit();
}

std::string SqliteJournalStore::fileOf(const std::string& volume) const {
  return (std::filesystem::path(dir_) / volume).string();
}

// The file first, durably, then its row: a row never names bytes that are not there.
void SqliteJournalStore::putVolume(const JournalVolumeRow& volume, LeaseToken) {
  const std::string file = fileOf(volume.name);
  std::filesystem::create_directories(std::filesystem::path(file).parent_path());
  std::filesystem::remove(file);  // one of the same name is replaced
  writeFileDurably(file, volume.bytes);
  try {
    SqliteTransaction transaction(*db_);
    db_->prepare("INSERT OR REPLACE INTO volumes (scene, name, size, crc) VALUES (?, ?, ?, ?)")
        .bind(1, volume.scene)
        .bindText(2, volume.name)
        .bind(3, int64_t(volume.bytes.size()))
        .bind(4, volume.crc)
        .run();
    transaction.commit();
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(file, ignored);
    throw;
  }
}

std::optional<JournalVolumeRow> SqliteJournalStore::readVolume(int64_t scene,
                                                               const std::string& name) {
  SqliteStatement row = db_->prepare("SELECT size, crc FROM volumes WHERE scene = ? AND name = ?");
  row.bind(1, scene).bindText(2, name);
  if (!row.step()) return std::nullopt;
  JournalVolumeRow volume{scene, name, "", row.columnInt(0), row.columnInt(1)};
  std::ifstream in(fileOf(name), std::ios::binary);
  std::ostringstream bytes;
  if (!(in && bytes << in.rdbuf()))
    throw std::runtime_error("the uploaded volume '" + fileOf(name) + "' cannot be read");
  volume.bytes = std::move(bytes).str();
  return volume;
}

std::vector<JournalVolumeRow> SqliteJournalStore::volumesOf(int64_t scene) {
  std::vector<JournalVolumeRow> volumes;
  SqliteStatement rows =
      db_->prepare("SELECT name, size, crc FROM volumes WHERE scene = ? ORDER BY name");
  rows.bind(1, scene);
  while (rows.step())
    volumes.push_back({scene, rows.columnBytes(0), "", rows.columnInt(1), rows.columnInt(2)});
  return volumes;
}

void SqliteJournalStore::deleteVolume(int64_t scene, const std::string& name, LeaseToken) {
  SqliteTransaction transaction(*db_);
  db_->prepare("DELETE FROM volumes WHERE scene = ? AND name = ?")
      .bind(1, scene)
      .bindText(2, name)
      .run();
  transaction.commit();
  std::error_code ignored;
  std::filesystem::remove(fileOf(name), ignored);
}

}  // namespace penumbra::server
