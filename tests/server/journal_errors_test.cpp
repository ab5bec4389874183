// How the journal's two database wrappers classify failures (postgres_statements.h,
// sqlite_db.h): a database that cannot serve now — a lost or silent connection, a statement cut
// by its timeout, a file locked by another writer — throws JournalUnavailable, which every route
// answers 503 journal_failed (retryable); a statement the database refuses for what it says — a
// syntax error, a broken constraint — throws a plain error, never taken for unavailability.
#include <gtest/gtest.h>
#include <libpq-fe.h>

#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "postgres_cluster.h"
#include "server/journal_unavailable.h"
#include "server/postgres_statements.h"
#include "server/sqlite_db.h"
#include "temp_data_dir.h"

namespace penumbra::server::test {
namespace {

// Runs `action`; "unavailable", "error" (another std::exception) or "none".
template <typename Action>
std::string thrownKind(Action action, std::string* message = nullptr) {
  try {
    action();
  } catch (const JournalUnavailable& error) {
    if (message) *message = error.what();
    return "unavailable";
  } catch (const std::exception& error) {
    if (message) *message = error.what();
    return "error";
  }
  return "none";
}

struct Connection {
  explicit Connection(const std::string& uri) : conn(pg::connect(uri)) {
    EXPECT_EQ(PQstatus(conn), CONNECTION_OK) << pg::errorOf(conn);
  }
  ~Connection() { PQfinish(conn); }
  PGconn* conn;
};

TEST(JournalErrors, PostgresRefusalsAreErrorsAndASilentOrTimedOutDatabaseIsUnavailable) {
  PostgresCluster& cluster = PostgresCluster::shared();
  const std::string uri = cluster.freshDatabase() + "&connect_timeout=1";
  Connection db(uri);
  pg::runScript(db.conn, "CREATE TABLE t (k bigint PRIMARY KEY)");
  pg::run(db.conn, "INSERT INTO t VALUES ($1)", pg::Params().add(int64_t(1)));

  std::string message;
  EXPECT_EQ(thrownKind([&] { pg::run(db.conn, "SELEC 1"); }, &message), "error") << message;
  EXPECT_EQ(thrownKind([&] { pg::run(db.conn, "INSERT INTO t VALUES ($1)",
                                     pg::Params().add(int64_t(1))); }, &message),
            "error")
      << message;
  EXPECT_EQ(thrownKind([&] {
              pg::eachRow(db.conn, "SELECT k FROM t WHERE k / 0 = 1", {}, [](const PGresult*) {});
            }, &message),
            "error")
      << message;
  // A row handler's own exception comes out as it was thrown.
  EXPECT_THROW(pg::eachRow(db.conn, "SELECT k FROM t", {},
                           [](const PGresult*) { throw std::out_of_range("the handler's"); }),
               std::out_of_range);

  // The session's statement timeout (sessionTimeouts: the answer timeout, 1 s) cuts a long one.
  pg::runScript(db.conn, pg::sessionTimeouts(db.conn).c_str());
  EXPECT_EQ(thrownKind([&] { pg::run(db.conn, "SELECT pg_sleep(3)"); }, &message), "unavailable")
      << message;
  EXPECT_EQ(PQstatus(db.conn), CONNECTION_OK) << "a timed-out statement keeps its connection";
  EXPECT_EQ(thrownKind([&] { pg::run(db.conn, "SELECT 1"); }), "none");

  cluster.pause();
  struct ResumeAtExit {
    PostgresCluster& cluster;
    ~ResumeAtExit() { cluster.resume(); }
  } resumeAtExit{cluster};
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(thrownKind([&] { pg::run(db.conn, "SELECT k FROM t"); }, &message), "unavailable")
      << message;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 3);
  EXPECT_NE(PQstatus(db.conn), CONNECTION_OK) << "the silent connection is cut";
  EXPECT_EQ(thrownKind([&] { pg::run(db.conn, "SELECT 1"); }, &message), "unavailable")
      << message;
  cluster.resume();
  PQreset(db.conn);
  EXPECT_EQ(thrownKind([&] { pg::run(db.conn, "SELECT k FROM t"); }), "none");

  cluster.stop();  // a fast shutdown ends the session: the next statement finds it gone
  EXPECT_EQ(thrownKind([&] { pg::run(db.conn, "SELECT 1"); }, &message), "unavailable")
      << message;
  cluster.start();
}

TEST(JournalErrors, SqliteRefusalsAreErrorsAndAFileLockedByAnotherWriterIsUnavailable) {
  const TempDataDir dir;
  std::filesystem::create_directories(dir.str());
  const std::string path = dir.str() + "/journal.sqlite3";
  SqliteDb db(path), other(path);
  db.exec("CREATE TABLE t (k INTEGER PRIMARY KEY)");
  db.exec("INSERT INTO t VALUES (1)");

  std::string message;
  EXPECT_EQ(thrownKind([&] { db.exec("SELEC 1"); }, &message), "error") << message;
  EXPECT_EQ(thrownKind([&] { db.prepare("INSERT INTO t VALUES (?)").bind(1, 1).run(); }, &message),
            "error")
      << message;
  EXPECT_EQ(thrownKind([&] { db.prepare("SELECT * FROM missing"); }, &message), "error")
      << message;

  other.setBusyTimeout(50);
  db.exec("BEGIN EXCLUSIVE");
  EXPECT_EQ(thrownKind([&] { other.prepare("INSERT INTO t VALUES (?)").bind(1, 2).run(); },
                       &message),
            "unavailable")
      << message;
  EXPECT_EQ(thrownKind([&] { other.exec("INSERT INTO t VALUES (3)"); }, &message), "unavailable")
      << message;
  db.exec("COMMIT");
  EXPECT_EQ(thrownKind([&] { other.exec("INSERT INTO t VALUES (3)"); }), "none");
}

}  // namespace
}  // namespace penumbra::server::test
