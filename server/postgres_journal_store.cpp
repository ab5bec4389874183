#include "server/postgres_journal_store.h"

#include <libpq-fe.h>

#include <stdexcept>

#include "server/postgres_statements.h"

namespace penumbra::server {

using namespace pg;

namespace {

// As the SQLite journal's tables (sqlite_journal_store.cpp), every number a BIGINT, and the
// scene leases. An uploaded volume's bytes are rows of volume_chunks (kVolumeChunk each: a 256 MiB
// upload is written and read a chunk per statement, never one huge value), stored uncompressed
// (EXTERNAL: NRRD data is raw or gzip already). Under a transaction-scoped advisory lock: nodes
// starting together on an empty database would otherwise race on CREATE TABLE IF NOT EXISTS (a
// unique violation in pg_type).
constexpr const char* kSchema = R"(
BEGIN;
SELECT pg_advisory_xact_lock(7039390);
CREATE TABLE IF NOT EXISTS scenes (
  key BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  id TEXT NOT NULL,
  name TEXT NOT NULL,
  base_version BIGINT NOT NULL,
  source BYTEA NOT NULL,
  source_crc BIGINT);
CREATE TABLE IF NOT EXISTS frames (
  scene BIGINT NOT NULL REFERENCES scenes(key) ON DELETE CASCADE,
  version BIGINT NOT NULL,
  frame BYTEA NOT NULL,
  parts BYTEA,
  crc BIGINT,
  parts_crc BIGINT,
  base BIGINT,
  PRIMARY KEY (scene, version));
CREATE TABLE IF NOT EXISTS snapshots (
  scene BIGINT NOT NULL REFERENCES scenes(key) ON DELETE CASCADE,
  version BIGINT NOT NULL,
  source BYTEA NOT NULL,
  parts BYTEA NOT NULL,
  crc BIGINT NOT NULL,
  PRIMARY KEY (scene, version));
CREATE INDEX IF NOT EXISTS scenes_by_id ON scenes (id);
CREATE TABLE IF NOT EXISTS volumes (
  scene BIGINT NOT NULL REFERENCES scenes(key) ON DELETE CASCADE,
  name TEXT NOT NULL,
  size BIGINT NOT NULL,
  crc BIGINT NOT NULL,
  PRIMARY KEY (scene, name));
CREATE TABLE IF NOT EXISTS volume_chunks (
  scene BIGINT NOT NULL,
  name TEXT NOT NULL,
  seq BIGINT NOT NULL,
  bytes BYTEA NOT NULL,
  PRIMARY KEY (scene, name, seq),
  FOREIGN KEY (scene, name) REFERENCES volumes ON DELETE CASCADE);
ALTER TABLE volume_chunks ALTER COLUMN bytes SET STORAGE EXTERNAL;
CREATE TABLE IF NOT EXISTS scene_leases (
  scene_id TEXT PRIMARY KEY,
  owner TEXT NOT NULL,
  token BIGINT NOT NULL,
  expires TIMESTAMPTZ NOT NULL,
  wanted_by TEXT);
COMMIT;
)";

// Inside a write's transaction: the scene's lease still holds `lease` (scene_leases.h), locked
// (FOR SHARE) until the commit, so a takeover waits for this write or this write sees its newer
// token. Throws LeaseLost otherwise.
void checkLease(PGconn* conn, const char* sql, const Params& params, LeaseToken lease,
                const std::string& scene) {
  if (!lease) return;
  if (PQntuples(run(conn, sql, params).get()) == 0)
    throw LeaseLost("scene '" + scene + "' is owned by another node now (its lease token " +
                    std::to_string(*lease) + " was taken over); nothing was written");
}

void checkLeaseOfKey(PGconn* conn, int64_t key, LeaseToken lease) {
  if (!lease) return;
  checkLease(conn,
             "SELECT 1 FROM scene_leases l JOIN scenes s ON s.id = l.scene_id WHERE s.key = $1 "
             "AND l.token = $2 FOR SHARE OF l",
             Params().add(key).add(*lease), lease, "#" + std::to_string(key));
}

// A read of the whole journal (every scene restored at start) may outlast the statement timeout:
// it runs without one (the answer timeout still ends a silent database), set again after it.
class WithoutStatementTimeout {
 public:
  explicit WithoutStatementTimeout(PGconn* conn) : conn_(conn) {
    runScript(conn_, "SET statement_timeout = 0");
  }
  ~WithoutStatementTimeout() {
    try {
      runScript(conn_, sessionTimeouts(conn_).c_str());
    } catch (const std::exception&) {  // a lost connection: configure() sets it on reconnecting
    }
  }
  WithoutStatementTimeout(const WithoutStatementTimeout&) = delete;
  WithoutStatementTimeout& operator=(const WithoutStatementTimeout&) = delete;

 private:
  PGconn* conn_;
};

constexpr size_t kVolumeChunk = size_t(8) << 20;

}  // namespace

PostgresJournalStore::PostgresJournalStore(const std::string& uri)
    : conn_(connect(uri)) {
  if (!conn_) throw std::runtime_error("the journal database cannot be opened: out of memory");
  if (PQstatus(conn_) != CONNECTION_OK) {
    const std::string message = errorOf(conn_);
    PQfinish(conn_);
    conn_ = nullptr;
    throw std::runtime_error("the journal database cannot be reached (" + message + ")");
  }
  // A socket directory is a host too: named as a parameter, as libpq reads it back.
  const std::string host = PQhost(conn_) ? PQhost(conn_) : "";
  const bool socket = host.rfind('/', 0) == 0;
  where_ = "postgresql://" + std::string(PQuser(conn_)) + "@" +
           (socket ? "" : host + ":" + PQport(conn_)) + "/" + PQdb(conn_) +
           (socket ? "?host=" + host : "");
  try {
    configure();
    runScript(conn_, kSchema);
  } catch (const std::exception& error) {
    PQfinish(conn_);
    conn_ = nullptr;
    throw std::runtime_error("the journal database " + where_ + " cannot be used (" + error.what() +
                             ")");
  }
}

PostgresJournalStore::~PostgresJournalStore() { PQfinish(conn_); }

void PostgresJournalStore::configure() {
  // A commit returns once its log is flushed on the database's disk, whatever the server's
  // default; the "already exists" notices of the schema are not news; a statement or a lock wait
  // that outlasts the answer timeout fails (sessionTimeouts).
  runScript(conn_, ("SET synchronous_commit = on; SET client_min_messages = warning; " +
                    sessionTimeouts(conn_))
                       .c_str());
}

std::string PostgresJournalStore::connectionProblem() const {
  if (PQstatus(conn_) == CONNECTION_OK) return "";
  return "the journal database " + where_ + " cannot be reached (" + errorOf(conn_) + ")";
}

std::string PostgresJournalStore::problem(bool ask) {
  if (PQstatus(conn_) == CONNECTION_OK && ask) {
    try {
      run(conn_, "SELECT 1");
    } catch (const std::exception& error) {
      if (PQstatus(conn_) == CONNECTION_OK)
        return "the journal database " + where_ + " does not answer (" + error.what() + ")";
    }
  }
  if (PQstatus(conn_) != CONNECTION_OK) {  // lost: the database restarted, or is still down
    PQreset(conn_);
    if (PQstatus(conn_) != CONNECTION_OK) return connectionProblem();
    try {
      configure();
    } catch (const std::exception& error) {
      return "the journal database " + where_ + " cannot be used (" + error.what() + ")";
    }
  }
  return "";
}

void PostgresJournalStore::readScenes(const std::function<void(JournalSceneRow&&)>& row) {
  const WithoutStatementTimeout unbounded(conn_);
  eachRow(conn_, "SELECT key, id, name, base_version, source, source_crc FROM scenes ORDER BY key", {},
          [&](const PGresult* r) {
            row({int8At(r, 0, 0), bytesAt(r, 0, 1), bytesAt(r, 0, 2), int8At(r, 0, 3),
                 bytesAt(r, 0, 4), optionalInt8At(r, 0, 5)});
          });
}

void PostgresJournalStore::readFrames(const std::function<void(JournalFrameRow&&)>& row) {
  const WithoutStatementTimeout unbounded(conn_);
  eachRow(conn_,
          "SELECT scene, version, frame, parts, crc, parts_crc, base FROM frames ORDER BY scene, "
          "version",
          {},
          [&](const PGresult* r) {
            row({int8At(r, 0, 0), int8At(r, 0, 1), bytesAt(r, 0, 2), bytesAt(r, 0, 3),
                 optionalInt8At(r, 0, 4), optionalInt8At(r, 0, 5), optionalInt8At(r, 0, 6)});
          });
}

void PostgresJournalStore::readSnapshots(const std::function<void(JournalSnapshotRow&&)>& row) {
  const WithoutStatementTimeout unbounded(conn_);
  eachRow(conn_, "SELECT scene, version, source, parts, crc FROM snapshots ORDER BY scene, version", {},
          [&](const PGresult* r) {
            row({int8At(r, 0, 0), int8At(r, 0, 1), bytesAt(r, 0, 2), bytesAt(r, 0, 3),
                 int8At(r, 0, 4)});
          });
}

std::optional<JournalSceneRow> PostgresJournalStore::sceneById(const std::string& id) {
  const Result r = run(conn_,
                       "SELECT key, id, name, base_version, source, source_crc FROM scenes WHERE "
                       "id = $1 ORDER BY key DESC LIMIT 1",
                       Params().text(id));
  if (PQntuples(r.get()) == 0) return std::nullopt;
  return JournalSceneRow{int8At(r.get(), 0, 0), bytesAt(r.get(), 0, 1), bytesAt(r.get(), 0, 2),
                         int8At(r.get(), 0, 3), bytesAt(r.get(), 0, 4),
                         optionalInt8At(r.get(), 0, 5)};
}

void PostgresJournalStore::readFramesOf(int64_t key,
                                        const std::function<void(JournalFrameRow&&)>& row) {
  eachRow(conn_,
          "SELECT scene, version, frame, parts, crc, parts_crc, base FROM frames WHERE scene = $1 "
          "ORDER BY version",
          Params().add(key), [&](const PGresult* r) {
            row({int8At(r, 0, 0), int8At(r, 0, 1), bytesAt(r, 0, 2), bytesAt(r, 0, 3),
                 optionalInt8At(r, 0, 4), optionalInt8At(r, 0, 5), optionalInt8At(r, 0, 6)});
          });
}

void PostgresJournalStore::readSnapshotsOf(int64_t key,
                                           const std::function<void(JournalSnapshotRow&&)>& row) {
  eachRow(conn_,
          "SELECT scene, version, source, parts, crc FROM snapshots WHERE scene = $1 ORDER BY "
          "version",
          Params().add(key), [&](const PGresult* r) {
            row({int8At(r, 0, 0), int8At(r, 0, 1), bytesAt(r, 0, 2), bytesAt(r, 0, 3),
                 int8At(r, 0, 4)});
          });
}

int64_t PostgresJournalStore::insertScene(const JournalSceneRow& scene, LeaseToken lease) {
  Transaction transaction(conn_);
  checkLease(conn_, "SELECT 1 FROM scene_leases WHERE scene_id = $1 AND token = $2 FOR SHARE",
             Params().text(scene.id).add(lease.value_or(0)), lease, scene.id);
  const Result key = run(conn_,
                         "INSERT INTO scenes (id, name, base_version, source, source_crc) VALUES "
                         "($1, $2, $3, $4, $5) RETURNING key",
                         Params()
                             .text(scene.id)
                             .text(scene.name)
                             .add(scene.baseVersion)
                             .bytes(scene.source)
                             .add(scene.sourceCrc));
  transaction.commit();
  return int8At(key.get(), 0, 0);
}

// A row already at this version can only be a commit whose answer a lost connection swallowed:
// never acknowledged (SceneJournal writes only the version after the last acknowledged one), so
// the frame that now takes that version replaces it rather than failing every retry.
void PostgresJournalStore::insertFrame(const JournalFrameRow& frame, LeaseToken lease) {
  Transaction transaction(conn_);
  checkLeaseOfKey(conn_, frame.scene, lease);
  run(conn_,
      "INSERT INTO frames (scene, version, frame, parts, crc, parts_crc, base) VALUES ($1, $2, "
      "$3, $4, $5, $6, $7) ON CONFLICT (scene, version) DO UPDATE SET frame = EXCLUDED.frame, "
      "parts = EXCLUDED.parts, crc = EXCLUDED.crc, parts_crc = EXCLUDED.parts_crc, base = "
      "EXCLUDED.base",
      Params()
          .add(frame.scene)
          .add(frame.version)
          .bytes(frame.frame)
          .bytes(frame.parts)
          .add(frame.crc)
          .add(frame.partsCrc)
          .add(frame.base));
  transaction.commit();
}

void PostgresJournalStore::putSnapshot(const JournalSnapshotRow& snapshot, size_t keep,
                                       LeaseToken lease) {
  Transaction transaction(conn_);
  checkLeaseOfKey(conn_, snapshot.scene, lease);
  run(conn_,
      "INSERT INTO snapshots (scene, version, source, parts, crc) VALUES ($1, $2, $3, $4, $5) "
      "ON CONFLICT (scene, version) DO UPDATE SET source = EXCLUDED.source, parts = "
      "EXCLUDED.parts, crc = EXCLUDED.crc",
      Params()
          .add(snapshot.scene)
          .add(snapshot.version)
          .bytes(snapshot.source)
          .bytes(snapshot.parts)
          .add(snapshot.crc));
  run(conn_,
      "DELETE FROM snapshots WHERE scene = $1 AND version NOT IN (SELECT version FROM snapshots "
      "WHERE scene = $1 ORDER BY version DESC LIMIT $2)",
      Params().add(snapshot.scene).add(int64_t(keep)));
  transaction.commit();
}

void PostgresJournalStore::deleteScene(int64_t key, LeaseToken lease) {
  Transaction transaction(conn_);
  checkLeaseOfKey(conn_, key, lease);
  run(conn_, "DELETE FROM scenes WHERE key = $1", Params().add(key));
  transaction.commit();
}

void PostgresJournalStore::renameScene(int64_t key, const std::string& name, LeaseToken lease) {
  Transaction transaction(conn_);
  checkLeaseOfKey(conn_, key, lease);
  run(conn_, "UPDATE scenes SET name = $1 WHERE key = $2", Params().text(name).add(key));
  transaction.commit();
}

void PostgresJournalStore::putVolume(const JournalVolumeRow& volume, LeaseToken lease) {
  Transaction transaction(conn_);
  checkLeaseOfKey(conn_, volume.scene, lease);
  run(conn_, "DELETE FROM volumes WHERE scene = $1 AND name = $2",
      Params().add(volume.scene).text(volume.name));
  run(conn_, "INSERT INTO volumes (scene, name, size, crc) VALUES ($1, $2, $3, $4)",
      Params()
          .add(volume.scene)
          .text(volume.name)
          .add(int64_t(volume.bytes.size()))
          .add(volume.crc));
  for (size_t at = 0, seq = 0; at < volume.bytes.size(); at += kVolumeChunk, ++seq)
    run(conn_, "INSERT INTO volume_chunks (scene, name, seq, bytes) VALUES ($1, $2, $3, $4)",
        Params()
            .add(volume.scene)
            .text(volume.name)
            .add(int64_t(seq))
            .bytes(volume.bytes.substr(at, kVolumeChunk)));
  transaction.commit();
}

std::optional<JournalVolumeRow> PostgresJournalStore::readVolume(int64_t scene,
                                                                 const std::string& name) {
  const Result row = run(conn_, "SELECT size, crc FROM volumes WHERE scene = $1 AND name = $2",
                         Params().add(scene).text(name));
  if (PQntuples(row.get()) == 0) return std::nullopt;
  JournalVolumeRow volume{scene, name, "", int8At(row.get(), 0, 0), int8At(row.get(), 0, 1)};
  volume.bytes.reserve(size_t(volume.size));
  eachRow(conn_, "SELECT bytes FROM volume_chunks WHERE scene = $1 AND name = $2 ORDER BY seq",
          Params().add(scene).text(name), [&](const PGresult* r) {
            volume.bytes.append(PQgetvalue(r, 0, 0), size_t(PQgetlength(r, 0, 0)));
          });
  return volume;
}

std::vector<JournalVolumeRow> PostgresJournalStore::volumesOf(int64_t scene) {
  std::vector<JournalVolumeRow> volumes;
  eachRow(conn_, "SELECT name, size, crc FROM volumes WHERE scene = $1 ORDER BY name",
          Params().add(scene), [&](const PGresult* r) {
            volumes.push_back({scene, bytesAt(r, 0, 0), "", int8At(r, 0, 1), int8At(r, 0, 2)});
          });
  return volumes;
}

void PostgresJournalStore::deleteVolume(int64_t scene, const std::string& name, LeaseToken lease) {
  Transaction transaction(conn_);
  checkLeaseOfKey(conn_, scene, lease);
  run(conn_, "DELETE FROM volumes WHERE scene = $1 AND name = $2", Params().add(scene).text(name));
  transaction.commit();
}

}  // namespace penumbra::server
