// One owner per scene among the nodes sharing a PostgreSQL journal (docs/SERVER.md "Many
// nodes"): a row per scene in scene_leases (its owner node, a fencing token that grows on every
// takeover, an expiry on the database's clock) taken, renewed and given up here, over a
// connection of its own; the journal's writes check the token (journal_store.h, LeaseToken).
// Thread-safe (one mutex around the connection).
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>

struct pg_conn;

namespace penumbra::server {

class SceneLeases {
 public:
  // Connects to `uri` (the journal's database, whose store made the table). Throws
  // std::runtime_error when it cannot.
  SceneLeases(const std::string& uri, std::string node, double leaseSeconds);
  ~SceneLeases();
  SceneLeases(const SceneLeases&) = delete;
  SceneLeases& operator=(const SceneLeases&) = delete;

  const std::string& node() const { return node_; }

  // Who holds a lease another node asked for, and for how long yet.
  struct Holder {
    std::string node;
    double secondsLeft = 0;
  };
  // Takes scene `id`'s lease when it is free (no row, expired, or this node's already): returns
  // its new token, greater than every token the scene had. Else nullopt, `holder` says who has
  // it, and the holder is asked to hand it over at its next renewal (renew's `wanted`).
  std::optional<int64_t> acquire(const std::string& id, Holder& holder);

  struct Renewal {
    std::map<std::string, int64_t> held;  // scene id → token of every lease this node holds
    std::set<std::string> wanted;         // those another node asked for
  };
  // Pushes the expiry of every lease this node holds one lease further.
  Renewal renew();
  // Gives `id`'s lease up (it expires now) if `token` is still its token.
  void release(const std::string& id, int64_t token);
  // release, where a failure (the database out of reach) is no error: the lease then expires
  // by itself within its length, so another node waits for it a little longer.
  void releaseOrLetExpire(const std::string& id, int64_t token) noexcept;

 private:
  void reconnect();  // a lost connection opened again; throws when it cannot be

  std::mutex mutex_;
  pg_conn* conn_ = nullptr;
  std::string node_;
  double leaseSeconds_;
};

}  // namespace penumbra::server
