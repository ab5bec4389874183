// A journal for the tests that run on both stores (journal_store.h): a fresh data directory and,
// on PostgreSQL, a fresh database of the binary's test cluster (postgres_cluster.h); raw SQL on
// it for the tests that look at or damage rows (the server stopped). Removed at scope exit (the
// database goes with the cluster).
#pragma once

#include <gtest/gtest.h>
#include <libpq-fe.h>
#include <sqlite3.h>

#include <ostream>
#include <string>

#include "postgres_cluster.h"
#include "temp_data_dir.h"

namespace penumbra::server::test {

enum class JournalBackend { Sqlite, Postgres };

inline void PrintTo(JournalBackend backend, std::ostream* out) {
  *out << (backend == JournalBackend::Sqlite ? "SQLite" : "PostgreSQL");
}

inline std::string backendName(const ::testing::TestParamInfo<JournalBackend>& info) {
  return info.param == JournalBackend::Sqlite ? "Sqlite" : "Postgres";
}

class TestJournal {
 public:
  explicit TestJournal(JournalBackend backend) {
    if (backend == JournalBackend::Postgres) database_ = PostgresCluster::shared().freshDatabase();
  }

  const TempDataDir& dir() const { return dir_; }
  const std::string& database() const { return database_; }  // empty: SQLite

  // Loopback server options journaling here.
  ServerOptions durable() const {
    ServerOptions options = dir_.durable();
    options.journalDatabase = database_;
    return options;
  }

  // Runs `statement` on the journal.
  void sql(const std::string& statement) const { query(statement, true); }
  // The first column of every row of `select`, joined by ','; NULL reads as "".
  std::string sqlText(const std::string& select) const { return query(select, false); }

 private:
  std::string query(const std::string& text, bool command) const {
    return database_.empty() ? sqliteQuery(text) : postgresQuery(text, command);
  }

  std::string sqliteQuery(const std::string& text) const {
    sqlite3* db = nullptr;
    EXPECT_EQ(sqlite3_open((dir_.str() + "/journal.sqlite3").c_str(), &db), SQLITE_OK);
    sqlite3_stmt* rows = nullptr;
    EXPECT_EQ(sqlite3_prepare_v2(db, text.c_str(), -1, &rows, nullptr), SQLITE_OK)
        << text << ": " << sqlite3_errmsg(db);
    std::string out;
    int rc = SQLITE_ROW;
    for (bool first = true; (rc = sqlite3_step(rows)) == SQLITE_ROW; first = false) {
      if (!first) out += ",";
      if (const void* bytes = sqlite3_column_blob(rows, 0))
        out.append(static_cast<const char*>(bytes), size_t(sqlite3_column_bytes(rows, 0)));
    }
    EXPECT_EQ(rc, SQLITE_DONE) << text << ": " << sqlite3_errmsg(db);
    sqlite3_finalize(rows);
    sqlite3_close(db);
    return out;
  }

  std::string postgresQuery(const std::string& text, bool command) const {
    PGconn* conn = PQconnectdb(database_.c_str());
    EXPECT_EQ(PQstatus(conn), CONNECTION_OK) << PQerrorMessage(conn);
    PGresult* result = PQexec(conn, text.c_str());
    EXPECT_EQ(PQresultStatus(result), command ? PGRES_COMMAND_OK : PGRES_TUPLES_OK)
        << text << ": " << PQerrorMessage(conn);
    std::string out;
    for (int row = 0; !command && row < PQntuples(result); ++row) {
      if (row) out += ",";
      const char* value = PQgetvalue(result, row, 0);
      if (PQftype(result, 0) != 17) {  // bytea comes back escaped
        out += value;
        continue;
      }
      size_t length = 0;
      unsigned char* bytes =
          PQunescapeBytea(reinterpret_cast<const unsigned char*>(value), &length);
      out.append(reinterpret_cast<const char*>(bytes), length);
      PQfreemem(bytes);
    }
    PQclear(result);
    PQfinish(conn);
    return out;
  }

  TempDataDir dir_;
  std::string database_;
};

}  // namespace penumbra::server::test
