// libpq at its simplest, for the PostgreSQL journal (postgres_journal_store.h) and the scene
// leases (scene_leases.h): a connection with TCP keepalives and timeouts, statements with binary
// parameters and results, rows one at a time, a transaction rolled back unless committed. Each
// error throws with the database's message: JournalUnavailable (journal_unavailable.h) when the
// database cannot serve now (the connection lost, a timeout, a shutdown, no disk or memory there),
// std::runtime_error for any other. A database that stops answering without closing the
// connection (a stopped or wedged server, a dead link) is unavailable after the connection's
// answer timeout, and the connection is cut. Stateless; a connection is used by one thread at a
// time.
#pragma once

#include <libpq-fe.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::server::pg {

// Type OIDs of the parameters (pg_type.h): sent in binary, as are the results.
constexpr Oid kInt8 = 20, kText = 25, kBytea = 17;

using Result = std::unique_ptr<PGresult, decltype(&PQclear)>;

// A statement's parameters in binary; NULL for an absent number.
class Params {
 public:
  Params& add(int64_t value);
  Params& add(std::optional<int64_t> value) { return value ? add(*value) : push("", kInt8, true); }
  Params& text(const std::string& value) { return push(value, kText, false); }
  Params& bytes(const std::string& value) { return push(value, kBytea, false); }

  int count() const { return int(bytes_.size()); }
  const Oid* types() const { return types_.data(); }
  // Pointers into the stored bytes: valid until the next add.
  std::vector<const char*> values() const;
  std::vector<int> lengths() const;
  std::vector<int> formats() const { return std::vector<int>(bytes_.size(), 1); }

 private:
  Params& push(std::string value, Oid type, bool null);
  std::vector<std::string> bytes_;
  std::vector<Oid> types_;
  std::vector<bool> null_;
};

// Opens a connection to `uri` (PQconnectdb's status to check) with these defaults under whatever
// the URI itself sets: connect_timeout 10 s, TCP keepalives probing an idle connection after 5 s,
// every 2 s, 3 times (a peer that vanished is noticed in about 11 s), and tcp_user_timeout 10 s
// (data sent and never acknowledged). Keepalives act on TCP only; answerSeconds bounds a unix
// socket's wait too.
PGconn* connect(const std::string& uri);
// How long a statement waits for the database: its connect_timeout (a URI's ?connect_timeout=S),
// the same bound as opening the connection. Also the session's statement_timeout and lock_timeout
// (sessionTimeouts).
int answerSeconds(PGconn* conn);
// The session settings at answerSeconds: statement_timeout and lock_timeout (a statement running
// longer, or waiting longer on a lock, fails) and idle_in_transaction_session_timeout (a node
// stalled inside a transaction loses its session, and with it the locks that would hold others).
std::string sessionTimeouts(PGconn* conn);

// The connection's last error, without its trailing newline.
std::string errorOf(PGconn* conn);
// Runs one statement; throws with the database's message unless it succeeded, or when the
// database sent nothing for answerSeconds (JournalUnavailable; the connection is then cut: the
// next use connects again).
Result run(PGconn* conn, const char* sql, const Params& params = {});
// Runs statements without parameters or rows (the schema, session settings), several at once.
void runScript(PGconn* conn, const char* sql);

int64_t int8At(const PGresult* result, int row, int column);
std::optional<int64_t> optionalInt8At(const PGresult* result, int row, int column);
std::string bytesAt(const PGresult* result, int row, int column);

// Hands each row of `sql` to `row` as it arrives (single-row mode: a large journal is never
// held whole); throws at the first error, after the rows before it.
void eachRow(PGconn* conn, const char* sql, const Params& params,
             const std::function<void(const PGresult*)>& row);

// BEGIN .. COMMIT; rolled back when left uncommitted (an exception), if the connection lives.
class Transaction {
 public:
  explicit Transaction(PGconn* conn) : conn_(conn) { run(conn_, "BEGIN"); }
  ~Transaction() {
    if (!open_ || PQstatus(conn_) != CONNECTION_OK) return;
    try {
      run(conn_, "ROLLBACK");
    } catch (const std::exception&) {  // the connection is gone: so is the transaction
    }
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

}  // namespace penumbra::server::pg
