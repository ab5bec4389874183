#include "server/postgres_statements.h"

#include <endian.h>
#include <poll.h>
#include <sys/socket.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <stdexcept>

#include "server/journal_unavailable.h"

namespace penumbra::server::pg {

namespace {

constexpr int kDefaultSeconds = 10;  // connect_timeout, when the URI says nothing

std::string head(const char* sql) { return std::string(sql).substr(0, 40); }

// SQLSTATEs that say the database cannot serve now, not that the statement is wrong: class 08
// (the connection), 53 (out of disk, memory or connections), 58 (the server's I/O), a shutdown or
// a start under way (57P01-57P03), a statement or lock wait cut by the session's timeouts (57014,
// 55P03, 25P03).
bool unavailableState(const std::string& state) {
  const std::string cls = state.substr(0, 2);
  return cls == "08" || cls == "53" || cls == "58" || state == "57P01" || state == "57P02" ||
         state == "57P03" || state == "57014" || state == "55P03" || state == "25P03";
}

// Throws JournalUnavailable when the connection is lost or `state` says the database cannot
// serve now (its callers answer 503, retryable), else std::runtime_error (a 500).
[[noreturn]] void fail(PGconn* conn, const std::string& message, const std::string& state = "") {
  if (PQstatus(conn) != CONNECTION_OK || unavailableState(state)) throw JournalUnavailable(message);
  throw std::runtime_error(message);
}

std::string stateOf(const PGresult* result) {
  const char* state = PQresultErrorField(result, PG_DIAG_SQLSTATE);
  return state ? state : "";
}

// Waits until the connection's socket is ready for `events`. A database silent for `seconds`
// (answerSeconds): the connection is cut (libpq then sees it closed; the next use opens it
// again) and this throws.
void await(PGconn* conn, short events, int seconds, const char* sql) {
  pollfd fd{PQsocket(conn), events, 0};
  int ready = 0;
  do ready = ::poll(&fd, 1, seconds * 1000);
  while (ready < 0 && errno == EINTR);
  if (ready > 0) return;
  if (fd.fd >= 0) ::shutdown(fd.fd, SHUT_RDWR);
  PQconsumeInput(conn);  // reads the end of the stream: CONNECTION_BAD
  throw JournalUnavailable(head(sql) + ": the database did not answer within " +
                           std::to_string(seconds) + " s (the connection was cut)");
}

// Sends the statement libpq holds. Nonblocking: a large parameter to a database that stopped
// reading waits in await, bounded, not in send().
void flush(PGconn* conn, int seconds, const char* sql) {
  for (;;) {
    const int left = PQflush(conn);
    if (left == 0) return;
    if (left < 0) fail(conn, head(sql) + ": " + errorOf(conn));
    await(conn, POLLOUT | POLLIN, seconds, sql);
    if (!PQconsumeInput(conn)) fail(conn, head(sql) + ": " + errorOf(conn));
  }
}

void send(PGconn* conn, const char* sql, const Params& params, bool singleRow, int seconds) {
  const std::vector<const char*> values = params.values();
  const std::vector<int> lengths = params.lengths(), formats = params.formats();
  if (PQsetnonblocking(conn, 1) != 0 ||
      !PQsendQueryParams(conn, sql, params.count(), params.types(), values.data(),
                         lengths.data(), formats.data(), 1) ||
      (singleRow && !PQsetSingleRowMode(conn)))
    fail(conn, head(sql) + ": " + errorOf(conn));
  flush(conn, seconds, sql);
}

// The next result of the statement in flight; null after its last.
PGresult* nextResult(PGconn* conn, int seconds, const char* sql) {
  while (PQisBusy(conn)) {
    await(conn, POLLIN, seconds, sql);
    if (!PQconsumeInput(conn)) fail(conn, head(sql) + ": " + errorOf(conn));
  }
  return PQgetResult(conn);
}

}  // namespace

PGconn* connect(const std::string& uri) {
  const std::string seconds = std::to_string(kDefaultSeconds);
  const char* keys[] = {"connect_timeout", "keepalives", "keepalives_idle",
                        "keepalives_interval", "keepalives_count", "tcp_user_timeout",
                        "dbname", nullptr};
  const std::string userTimeout = std::to_string(kDefaultSeconds * 1000);
  // The URI comes last: what it sets overrides these defaults.
  const char* values[] = {seconds.c_str(), "1", "5", "2", "3", userTimeout.c_str(), uri.c_str(),
                          nullptr};
  return PQconnectdbParams(keys, values, 1);
}

int answerSeconds(PGconn* conn) {
  int seconds = kDefaultSeconds;
  PQconninfoOption* options = PQconninfo(conn);
  for (PQconninfoOption* option = options; option && option->keyword; ++option)
    if (option->val && std::strcmp(option->keyword, "connect_timeout") == 0 &&
        std::atoi(option->val) > 0)
      seconds = std::atoi(option->val);
  PQconninfoFree(options);
  return seconds;
}

std::string sessionTimeouts(PGconn* conn) {
  const std::string bound = "'" + std::to_string(answerSeconds(conn)) + "s'";
  return "SET statement_timeout = " + bound + "; SET lock_timeout = " + bound +
         "; SET idle_in_transaction_session_timeout = " + bound;
}

Params& Params::add(int64_t value) {
  const uint64_t big = htobe64(uint64_t(value));
  return push(std::string(reinterpret_cast<const char*>(&big), 8), kInt8, false);
}

std::vector<const char*> Params::values() const {
  std::vector<const char*> out;
  for (size_t i = 0; i < bytes_.size(); ++i) out.push_back(null_[i] ? nullptr : bytes_[i].data());
  return out;
}

std::vector<int> Params::lengths() const {
  std::vector<int> out;
  for (const std::string& b : bytes_) out.push_back(int(b.size()));
  return out;
}

Params& Params::push(std::string value, Oid type, bool null) {
  bytes_.push_back(std::move(value));
  types_.push_back(type);
  null_.push_back(null);
  return *this;
}

std::string errorOf(PGconn* conn) {
  std::string message = PQerrorMessage(conn);
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  return message;
}

Result run(PGconn* conn, const char* sql, const Params& params) {
  const int seconds = answerSeconds(conn);
  send(conn, sql, params, false, seconds);
  Result result(nullptr, &PQclear);
  std::string error, state;
  // Every result is read (one for one statement), so that the connection is ready for the next.
  while (PGresult* next = nextResult(conn, seconds, sql)) {
    const ExecStatusType status = PQresultStatus(next);
    if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK && error.empty()) {
      error = head(sql) + ": " + errorOf(conn);
      state = stateOf(next);
    }
    if (result) PQclear(next);
    else result.reset(next);
  }
  if (!result && error.empty()) error = head(sql) + ": " + errorOf(conn);
  if (!error.empty()) fail(conn, error, state);
  return result;
}

void runScript(PGconn* conn, const char* sql) {
  const int seconds = answerSeconds(conn);
  if (PQsetnonblocking(conn, 1) != 0 || !PQsendQuery(conn, sql))
    fail(conn, head(sql) + ": " + errorOf(conn));
  flush(conn, seconds, sql);
  std::string error, state;
  while (PGresult* next = nextResult(conn, seconds, sql)) {
    const Result result(next, &PQclear);
    const ExecStatusType status = PQresultStatus(next);
    if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK && error.empty()) {
      error = head(sql) + ": " + errorOf(conn);
      state = stateOf(next);
    }
  }
  if (!error.empty()) fail(conn, error, state);
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

void eachRow(PGconn* conn, const char* sql, const Params& params,
             const std::function<void(const PGresult*)>& row) {
  const int seconds = answerSeconds(conn);
  send(conn, sql, params, true, seconds);
  std::string error, state;
  std::exception_ptr thrownByRow;  // rethrown as it was, after the statement's last result
  // Every result is read, even after an error, so that the connection is ready for the next.
  while (PGresult* next = nextResult(conn, seconds, sql)) {
    const Result result(next, &PQclear);
    const ExecStatusType status = PQresultStatus(next);
    if (status == PGRES_SINGLE_TUPLE && error.empty() && !thrownByRow) {
      try {
        row(next);
      } catch (...) {
        thrownByRow = std::current_exception();
      }
    } else if (status != PGRES_TUPLES_OK && status != PGRES_SINGLE_TUPLE && error.empty()) {
      error = head(sql) + ": " + errorOf(conn);
      state = stateOf(next);
    }
  }
  if (!error.empty()) fail(conn, error, state);
  if (thrownByRow) std::rethrow_exception(thrownByRow);
}

}  // namespace penumbra::server::pg
