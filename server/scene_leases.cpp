#include "server/scene_leases.h"

#include <libpq-fe.h>

#include <stdexcept>

#include "server/journal_unavailable.h"
#include "server/postgres_statements.h"

namespace penumbra::server {

using namespace pg;

namespace {

// A lease's length as a parameter: milliseconds, so that fractions of a second work too.
int64_t millis(double seconds) { return int64_t(seconds * 1000); }

}  // namespace

SceneLeases::SceneLeases(const std::string& uri, std::string node, double leaseSeconds)
    : conn_(connect(uri)), node_(std::move(node)), leaseSeconds_(leaseSeconds) {
  try {
    if (!conn_ || PQstatus(conn_) != CONNECTION_OK)
      throw std::runtime_error(conn_ ? errorOf(conn_) : "out of memory");
    runScript(conn_, sessionTimeouts(conn_).c_str());
  } catch (const std::exception& error) {
    PQfinish(conn_);
    conn_ = nullptr;
    throw std::runtime_error("the scene leases' database cannot be reached (" +
                             std::string(error.what()) + ")");
  }
}

SceneLeases::~SceneLeases() { PQfinish(conn_); }

void SceneLeases::reconnect() {
  if (PQstatus(conn_) == CONNECTION_OK) return;
  PQreset(conn_);
  if (PQstatus(conn_) != CONNECTION_OK)
    throw JournalUnavailable("the scene leases' database cannot be reached (" + errorOf(conn_) +
                             ")");
  runScript(conn_, sessionTimeouts(conn_).c_str());  // a new session: its timeouts again
}

std::optional<int64_t> SceneLeases::acquire(const std::string& id, Holder& holder) {
  std::lock_guard lock(mutex_);
  reconnect();
  // The row lock of the update waits for a journal write holding the old token (FOR SHARE):
  // that write commits first, and is in what the new owner restores.
  const Result taken =
      run(conn_,
          "INSERT INTO scene_leases (scene_id, owner, token, expires) VALUES ($1, $2, 1, now() + "
          "$3 * interval '1 millisecond') ON CONFLICT (scene_id) DO UPDATE SET owner = $2, token "
          "= scene_leases.token + 1, expires = EXCLUDED.expires, wanted_by = NULL WHERE "
          "scene_leases.expires < now() OR scene_leases.owner = $2 RETURNING token",
          Params().text(id).text(node_).add(millis(leaseSeconds_)));
  if (PQntuples(taken.get()) == 1) return int8At(taken.get(), 0, 0);
  const Result asked = run(conn_,
                           "UPDATE scene_leases SET wanted_by = $2 WHERE scene_id = $1 RETURNING "
                           "owner, (extract(epoch FROM expires - now()) * 1000)::bigint",
                           Params().text(id).text(node_));
  if (PQntuples(asked.get()) == 1) {
    holder.node = bytesAt(asked.get(), 0, 0);
    holder.secondsLeft = double(int8At(asked.get(), 0, 1)) / 1000;
  }
  return std::nullopt;
}

SceneLeases::Renewal SceneLeases::renew() {
  std::lock_guard lock(mutex_);
  reconnect();
  const Result rows = run(conn_,
                          "UPDATE scene_leases SET expires = now() + $2 * interval '1 millisecond' "
                          "WHERE owner = $1 RETURNING scene_id, token, wanted_by IS NOT NULL",
                          Params().text(node_).add(millis(leaseSeconds_)));
  Renewal renewal;
  for (int row = 0; row < PQntuples(rows.get()); ++row) {
    const std::string id = bytesAt(rows.get(), row, 0);
    renewal.held[id] = int8At(rows.get(), row, 1);
    if (*PQgetvalue(rows.get(), row, 2)) renewal.wanted.insert(id);  // binary bool: 1 byte
  }
  return renewal;
}

void SceneLeases::release(const std::string& id, int64_t token) {
  std::lock_guard lock(mutex_);
  reconnect();
  run(conn_,
      "UPDATE scene_leases SET expires = now(), wanted_by = NULL WHERE scene_id = $1 AND owner = "
      "$2 AND token = $3",
      Params().text(id).text(node_).add(token));
}

void SceneLeases::releaseOrLetExpire(const std::string& id, int64_t token) noexcept {
  try {
    release(id, token);
  } catch (const std::exception&) {
  }
}

}  // namespace penumbra::server
