#include "server/postgres_journal_store.h"

#include <endian.h>
#include <libpq-fe.h>

#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

namespace penumbra::server {

namespace {

// As the SQLite journal's tables (sqlite_journal_store.cpp), every number a BIGINT.
constexpr const char* kSchema = R"(
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
)";

// Type OIDs of the parameters (pg_type.h): sent in binary, as are the results.
constexpr Oid kInt8 = 20, kText = 25, kBytea = 17;

using Result = std::unique_ptr<PGresult, decltype(&PQclear)>;

// A statement's parameters in binary; NULL for an absent number.
class Params {
 public:
  Params& add(int64_t value) {
    const uint64_t big = htobe64(uint64_t(value));
    return push(std::string(reinterpret_cast<const char*>(&big), 8), kInt8, false);
  }
  Params& add(std::optional<int64_t> value) { return value ? add(*value) : push("", kInt8, true); }
  Params& text(const std::string& value) { return push(value, kText, false); }
  Params& bytes(const std::string& value) { return push(value, kBytea, false); }

  int count() const { return int(bytes_.size()); }
  const Oid* types() const { return types_.data(); }
  // Pointers into the stored bytes: valid until the next add.
  std::vector<const char*> values() const {
    std::vector<const char*> out;
    for (size_t i = 0; i < bytes_.size(); ++i) out.push_back(null_[i] ? nullptr : bytes_[i].data());
    return out;
  }
  std::vector<int> lengths() const {
    std::vector<int> out;
    for (const std::string& b : bytes_) out.push_back(int(b.size()));
    return out;
  }
  std::vector<int> formats() const { return std::vector<int>(bytes_.size(), 1); }

 private:
  Params& push(std::string value, Oid type, bool null) {
    bytes_.push_back(std::move(value));
    types_.push_back(type);
    null_.push_back(null);
    return *this;
  }
  std::vector<std::string> bytes_;
  std::vector<Oid> types_;
  std::vector<bool> null_;
};

std::string errorOf(PGconn* conn) {
  std::string message = PQerrorMessage(conn);
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  return message;
}

// Runs one statement; throws std::runtime_error with the database's message unless it succeeded.
Result run(PGconn* conn, const char* sql, const Params& params = {}) {
  const std::vector<const char*> values = params.values();
  const std::vector<int> lengths = params.lengths(), formats = params.formats();
  Result result(PQexecParams(conn, sql, params.count(), params.types(), values.data(),
                             lengths.data(), formats.data(), 1),
                &PQclear);
  const ExecStatusType status = result ? PQresultStatus(result.get()) : PGRES_FATAL_ERROR;
  if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK)
    throw std::runtime_error(std::string(sql).substr(0, 40) + ": " + errorOf(conn));
  return result;
}

// Runs statements without parameters or rows (the schema, session settings), several at once.
void runScript(PGconn* conn, const char* sql) {
  const Result result(PQexec(conn, sql), &PQclear);
  if (!result || PQresultStatus(result.get()) != PGRES_COMMAND_OK)
    throw std::runtime_error(std::string(sql).substr(0, 40) + ": " + errorOf(conn));
}

int64_t int8At(const PGresult* result, int row, int column) {
  uint64_t big = 0;
  std::memcpy(&big, PQgetvalue(result, row, column), sizeof big);
  return int64_t(be64toh(big));
}

std::optional<int64_t> optionalInt8At(const PGresult* result, int row, int column) {
  if (PQgetisnull(result, row, column)) return std::nullopt;
  return int8At(result, row, column);
}

std::string bytesAt(const PGresult* result, int row, int column) {
  return std::string(PQgetvalue(result, row, column), size_t(PQgetlength(result, row, column)));
}

// Hands each row of `sql` to `row` as it arrives (single-row mode: a large journal is never
// held whole); throws at the first error, after the rows before it.
void eachRow(PGconn* conn, const char* sql, const std::function<void(const PGresult*)>& row) {
  if (!PQsendQueryParams(conn, sql, 0, nullptr, nullptr, nullptr, nullptr, 1) ||
      !PQsetSingleRowMode(conn))
    throw std::runtime_error(std::string(sql).substr(0, 40) + ": " + errorOf(conn));
  std::string error;
  // Every result is read, even after an error, so that the connection is ready for the next.
  while (PGresult* next = PQgetResult(conn)) {
    const Result result(next, &PQclear);
    const ExecStatusType status = PQresultStatus(next);
    if (status == PGRES_SINGLE_TUPLE && error.empty()) {
      try {
        row(next);
      } catch (const std::exception& thrown) {
        error = thrown.what();
      }
    } else if (status != PGRES_TUPLES_OK && status != PGRES_SINGLE_TUPLE && error.empty()) {
      error = std::string(sql).substr(0, 40) + ": " + errorOf(conn);
    }
  }
  if (!error.empty()) throw std::runtime_error(error);
}

// BEGIN .. COMMIT; rolled back when left uncommitted (an exception), if the connection lives.
class Transaction {
 public:
  explicit Transaction(PGconn* conn) : conn_(conn) { run(conn_, "BEGIN"); }
  ~Transaction() {
    if (open_ && PQstatus(conn_) == CONNECTION_OK) PQclear(PQexec(conn_, "ROLLBACK"));
  }
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  void commit() {
    open_ = false;  // a failed COMMIT has ended the transaction too
    run(conn_, "COMMIT");
  }

 private:
  PGconn* conn_;
  bool open_ = true;
};

}  // namespace

PostgresJournalStore::PostgresJournalStore(const std::string& uri)
    : conn_(PQconnectdb(uri.c_str())) {
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
  // default; the "already exists" notices of the schema are not news.
  runScript(conn_, "SET synchronous_commit = on; SET client_min_messages = warning");
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
  eachRow(conn_, "SELECT key, id, name, base_version, source, source_crc FROM scenes ORDER BY key",
          [&](const PGresult* r) {
            row({int8At(r, 0, 0), bytesAt(r, 0, 1), bytesAt(r, 0, 2), int8At(r, 0, 3),
                 bytesAt(r, 0, 4), optionalInt8At(r, 0, 5)});
          });
}

void PostgresJournalStore::readFrames(const std::function<void(JournalFrameRow&&)>& row) {
  eachRow(conn_,
          "SELECT scene, version, frame, parts, crc, parts_crc, base FROM frames ORDER BY scene, "
          "version",
          [&](const PGresult* r) {
            row({int8At(r, 0, 0), int8At(r, 0, 1), bytesAt(r, 0, 2), bytesAt(r, 0, 3),
                 optionalInt8At(r, 0, 4), optionalInt8At(r, 0, 5), optionalInt8At(r, 0, 6)});
          });
}

void PostgresJournalStore::readSnapshots(const std::function<void(JournalSnapshotRow&&)>& row) {
  eachRow(conn_, "SELECT scene, version, source, parts, crc FROM snapshots ORDER BY scene, version",
          [&](const PGresult* r) {
            row({int8At(r, 0, 0), int8At(r, 0, 1), bytesAt(r, 0, 2), bytesAt(r, 0, 3),
                 int8At(r, 0, 4)});
          });
}

int64_t PostgresJournalStore::insertScene(const JournalSceneRow& scene) {
  Transaction transaction(conn_);
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
void PostgresJournalStore::insertFrame(const JournalFrameRow& frame) {
  Transaction transaction(conn_);
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

void PostgresJournalStore::putSnapshot(const JournalSnapshotRow& snapshot, size_t keep) {
  Transaction transaction(conn_);
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

void PostgresJournalStore::deleteScene(int64_t key) {
  Transaction transaction(conn_);
  run(conn_, "DELETE FROM scenes WHERE key = $1", Params().add(key));
  transaction.commit();
}

void PostgresJournalStore::renameScene(int64_t key, const std::string& name) {
  Transaction transaction(conn_);
  run(conn_, "UPDATE scenes SET name = $1 WHERE key = $2", Params().text(name).add(key));
  transaction.commit();
}

}  // namespace penumbra::server
