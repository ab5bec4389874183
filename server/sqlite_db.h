// A small RAII wrapper over SQLite's C API (libsqlite3): a connection and prepared statements,
// every failure thrown with SQLite's message: SqliteUnavailable when the file cannot be used now
// (I/O error, disk full, read-only, locked or busy past the timeout), SqliteError for any other.
// Not thread-safe: callers serialise use.
#pragma once

#include <sqlite3.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "server/journal_unavailable.h"

namespace penumbra::server {

struct SqliteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The journal's file cannot be used now: its requests answer 503, retryable.
struct SqliteUnavailable : JournalUnavailable {
  using JournalUnavailable::JournalUnavailable;
};

class SqliteStatement;

class SqliteDb {
 public:
  // Opens (creating) the database file; throws SqliteError.
  explicit SqliteDb(const std::string& path);
  ~SqliteDb();
  SqliteDb(const SqliteDb&) = delete;
  SqliteDb& operator=(const SqliteDb&) = delete;

  // Runs statements without results (schema, pragmas, BEGIN/COMMIT).
  void exec(const std::string& sql);
  // The first column of the first row of a query as text (pragmas that answer a value).
  std::string queryText(const std::string& sql);
  SqliteStatement prepare(const std::string& sql);
  void setBusyTimeout(int milliseconds);
  // Throws for the connection's last error: SqliteUnavailable or SqliteError (see the top).
  [[noreturn]] void fail(const std::string& what) const;
  sqlite3* handle() const { return db_; }

 private:
  sqlite3* db_ = nullptr;
};

class SqliteStatement {
 public:
  SqliteStatement(SqliteDb& db, const std::string& sql);
  ~SqliteStatement();
  SqliteStatement(SqliteStatement&& other) noexcept;
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;
  SqliteStatement& operator=(SqliteStatement&&) = delete;

  // Binds parameter `index` (1-based); blobs and text are copied by SQLite.
  SqliteStatement& bind(int index, int64_t value);
  SqliteStatement& bindText(int index, std::string_view text);
  SqliteStatement& bindBlob(int index, std::string_view bytes);
  // Steps once: true while a row is available, false when done. Throws SqliteError.
  bool step();
  // Runs to completion (statements without rows), then resets for reuse.
  void run();
  void reset();

  int64_t columnInt(int column) const;
  bool columnIsNull(int column) const;
  std::string columnBytes(int column) const;  // text or blob

 private:
  SqliteDb* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

// BEGIN IMMEDIATE .. COMMIT; rolls back when destroyed uncommitted (an exception left the scope).
class SqliteTransaction {
 public:
  explicit SqliteTransaction(SqliteDb& db);
  ~SqliteTransaction();
  SqliteTransaction(const SqliteTransaction&) = delete;
  SqliteTransaction& operator=(const SqliteTransaction&) = delete;
  void commit();

 private:
  SqliteDb& db_;
  bool open_ = true;
};

}  // namespace penumbra::server
