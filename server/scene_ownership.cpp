// One owner per scene among the nodes sharing a PostgreSQL journal (docs/SERVER.md "Many
// nodes"): a scene is served here only while this node holds its lease (scene_leases.h). A
// request for a scene served nowhere takes it over and restores it from the journal; one held
// by another node answers 503 + Retry-After (and asks that node to hand it over). A thread renews
// the leases, drops the scenes whose lease was lost, handed over or idle, and gives every lease
// back when the server stops.
#include <unistd.h>

#include <cmath>
#include <cstdio>

#include "server/api_errors.h"
#include "server/http_server.h"

namespace penumbra::server {

namespace {

using Clock = std::chrono::steady_clock;

// hostname:port; a server on any free port (tests) is told apart by its process and address.
std::string defaultNodeId(int port, const void* server) {
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) != 0) std::snprintf(host, sizeof host, "localhost");
  if (port != 0) return std::string(host) + ":" + std::to_string(port);
  char unique[64];
  std::snprintf(unique, sizeof unique, ":0/%d/%p", int(getpid()), server);
  return host + std::string(unique);
}

}  // namespace

void HttpServer::startLeases() {
  const std::string node =
      options_.nodeId.empty() ? defaultNodeId(options_.port, this) : options_.nodeId;
  leases_ = std::make_unique<SceneLeases>(options_.journalDatabase, node, options_.leaseSeconds);
  leaseKeeper_ = std::thread([this] { keepLeases(); });
}

void HttpServer::stopLeases() {
  if (!leases_) return;
  {
    std::lock_guard lock(leaseStopMutex_);
    if (leasesStopping_) return;
    leasesStopping_ = true;
  }
  leaseStop_.notify_all();
  if (leaseKeeper_.joinable()) leaseKeeper_.join();
  std::map<std::string, int64_t> held;
  {
    std::lock_guard lock(scenesMutex_);
    held.swap(leaseTokens_);
    for (const auto& [id, token] : held)
      if (const auto it = scenes_.find(id); it != scenes_.end() && it->second) it->second->close();
  }
  for (const auto& [id, token] : held) {  // handed back: another node need not wait for expiry
    leases_->releaseOrLetExpire(id, token);
  }
}

std::shared_ptr<SceneSession> HttpServer::takeOver(const std::string& id) {
  std::shared_ptr<RestoreJob> job;  // reserved by findScene; a DELETE or a stop cancels it
  {
    std::lock_guard lock(scenesMutex_);
    if (const auto it = restoring_.find(id); it != restoring_.end()) job = it->second;
  }
  if (!job) job = std::make_shared<RestoreJob>(id);
  std::optional<int64_t> token;
  auto unreserve = [&](RestoreJob::Ended ended = {}) {
    {
      std::lock_guard lock(scenesMutex_);
      scenes_.erase(id);
      restoring_.erase(id);
      leaseTokens_.erase(id);
    }
    if (token) {
      leases_->releaseOrLetExpire(id, *token);
    }
    job->end(std::move(ended));
  };
  SceneLeases::Holder holder;
  std::optional<SceneJournal::StoredScene> stored;
  try {
    if (!journal_->hasScene(id)) {
      unreserve();
      throw ApiError(404, error_code::kNotFound, "id", "no scene with id '" + id + "'");
    }
    token = leases_->acquire(id, holder);
    if (token) {
      {
        std::lock_guard lock(scenesMutex_);
        leaseTokens_[id] = *token;  // renewed from now on, while it restores
      }
      stored = journal_->loadScene(id, *token);
    }
  } catch (const ApiError&) {
    throw;
  } catch (const std::exception& error) {
    unreserve();
    throw ApiError(503, error_code::kJournalFailed, "",
                   "scene '" + id + "' cannot be taken over (" + error.what() + ")");
  }
  if (!token) {
    unreserve();
    throw ApiError(503, error_code::kOwnedElsewhere, "id",
                   "scene '" + id + "' is served by node " + holder.node + " (its lease ends in " +
                       std::to_string(int(std::ceil(std::max(holder.secondsLeft, 0.0)))) +
                       " s, and it was asked to hand it over); retry in a moment");
  }
  if (!stored) {  // deleted between the two reads
    unreserve();
    throw ApiError(404, error_code::kNotFound, "id", "no scene with id '" + id + "'");
  }
  RestoredScene report;
  std::shared_ptr<SceneSession> session;
  try {
    session = restoreStored(*stored, report, *job);
  } catch (const BuildCancelled&) {  // a DELETE of the scene, or a stop
    const RestoreJob::Ended ended = dropCancelledRestore(id, stored->key, *job);
    journal_->forgetScene(stored->key);
    unreserve(ended);
    if (ended.deleted)
      throw ApiError(404, error_code::kNotFound, "id",
                     "scene '" + id + "' was deleted while it was being restored");
    throw ApiError(503, error_code::kRestoring, "id",
                   "the restore of scene '" + id + "' was cancelled (" +
                       (ended.problem.empty() ? "the server is stopping"
                                              : "its deletion failed: " + ended.problem) +
                       "); retry");
  } catch (...) {
    unreserve();
    throw;
  }
  if (!session) {
    journal_->forgetScene(stored->key);
    unreserve();
    throw ApiError(409, error_code::kSceneStalled, "id",
                   "scene '" + id + "' is kept in the journal but not served: " + report.problem);
  }
  std::fprintf(stderr, "penumbra serve: took scene '%s' over (lease %lld), back at version %llu "
               "in %.2f s\n", id.c_str(), static_cast<long long>(*token),
               static_cast<unsigned long long>(report.version), report.seconds);
  {
    std::lock_guard lock(scenesMutex_);
    restoring_.erase(id);
    journalKeys_[session.get()] = stored->key;
    if (report.stalledAt) stalls_[session.get()] = SceneStall{*report.stalledAt, report.problem};
    lastUse_[id] = Clock::now();
    scenes_[id] = session;
  }
  job->end({true, false, ""});
  return session;
}

bool HttpServer::claimNewId(const std::string& id) {
  SceneLeases::Holder holder;
  const std::optional<int64_t> token = leases_->acquire(id, holder);
  if (!token) return false;
  if (journal_->hasScene(id)) {  // journaled, served nowhere now: a request brings it back
    leases_->releaseOrLetExpire(id, *token);
    return false;
  }
  std::lock_guard lock(scenesMutex_);
  leaseTokens_[id] = *token;
  return true;
}

void HttpServer::takeLeasesOf(std::vector<SceneJournal::StoredScene>& scenes) {
  std::vector<SceneJournal::StoredScene> mine;
  for (SceneJournal::StoredScene& stored : scenes) {
    SceneLeases::Holder holder;
    const std::optional<int64_t> token = leases_->acquire(stored.id, holder);
    if (!token) continue;  // another node serves it
    journal_->holdLease(stored.key, *token);
    {
      std::lock_guard lock(scenesMutex_);
      leaseTokens_[stored.id] = *token;
    }
    mine.push_back(std::move(stored));
  }
  scenes = std::move(mine);
}

std::optional<int64_t> HttpServer::dropScene(const std::string& id, const std::string& why) {
  std::shared_ptr<SceneSession> session;
  std::optional<int64_t> token;
  int64_t key = -1;
  {
    std::lock_guard lock(scenesMutex_);
    if (const auto it = leaseTokens_.find(id); it != leaseTokens_.end()) {
      token = it->second;
      leaseTokens_.erase(it);
    }
    lastUse_.erase(id);
    const auto it = scenes_.find(id);
    if (it == scenes_.end() || !it->second) return token;  // building or restoring: theirs
    session = it->second;
    // This node's copies of its uploads go (the journal keeps them; a node that serves it next
    // fetches them): before the id is free, so that no takeover here fetches them first.
    removeUploadsOf(id);
    scenes_.erase(it);
    if (const auto keyIt = journalKeys_.find(session.get()); keyIt != journalKeys_.end()) {
      key = keyIt->second;
      journalKeys_.erase(keyIt);
    }
    stalls_.erase(session.get());
  }
  if (key >= 0) journal_->forgetScene(key);
  session->close();  // its event streams end: clients reconnect to the new owner
  std::fprintf(stderr, "penumbra serve: no longer serving scene '%s': %s\n", id.c_str(),
               why.c_str());
  return token;
}

void HttpServer::keepLeases() {
  const auto every = std::chrono::duration<double>(options_.leaseSeconds / 3);
  for (;;) {
    {
      std::unique_lock lock(leaseStopMutex_);
      if (leaseStop_.wait_for(lock, every, [this] { return leasesStopping_; })) return;
    }
    try {
      renewLeasesOnce();
    } catch (const std::exception& error) {
      std::fprintf(stderr, "penumbra serve: renewing the scene leases failed: %s\n",
                   error.what());
    }
  }
}

void HttpServer::renewLeasesOnce() {
  std::map<std::string, int64_t> before;  // judged by the renewal (later takeovers are not)
  {
    std::lock_guard lock(scenesMutex_);
    before = leaseTokens_;
  }
  SceneLeases::Renewal renewal;
  try {
    renewal = leases_->renew();
  } catch (const std::exception&) {
    // Unrenewed past its length, a lease may be another node's now: serve nothing held by it.
    if (Clock::now() - leasesRenewedAt_ > std::chrono::duration<double>(options_.leaseSeconds))
      for (const auto& [id, token] : before) dropScene(id, "its lease could not be renewed");
    throw;
  }
  leasesRenewedAt_ = Clock::now();
  const auto idleAfter = std::chrono::duration<double>(options_.idleReleaseSeconds);
  std::vector<std::string> lost, handOver;
  std::vector<std::pair<std::string, int64_t>> stray;  // rows of this node it does not serve
  {
    std::lock_guard lock(scenesMutex_);
    for (const auto& [id, token] : before) {
      const auto now = leaseTokens_.find(id);
      if (now == leaseTokens_.end() || now->second != token) continue;  // dropped, taken again
      const auto renewed = renewal.held.find(id);
      if (renewed == renewal.held.end() || renewed->second != token) {
        lost.push_back(id);
        continue;
      }
      const auto served = scenes_.find(id);
      if (served == scenes_.end() || !served->second) continue;  // building or restoring
      const auto used = lastUse_.find(id);
      const bool idle = used != lastUse_.end() && Clock::now() - used->second > idleAfter &&
                        served->second.use_count() == 1;  // no request or stream holds it
      if (renewal.wanted.count(id) || idle) handOver.push_back(id);
    }
    for (const auto& [id, token] : renewal.held)
      if (!before.count(id) && !leaseTokens_.count(id)) stray.emplace_back(id, token);
  }
  for (const std::string& id : lost) dropScene(id, "another node took its lease over");
  for (const std::string& id : handOver)
    if (const std::optional<int64_t> token =
            dropScene(id, renewal.wanted.count(id) ? "handed over to the node asking for it"
                                                   : "idle: its lease is given back"))
      leases_->releaseOrLetExpire(id, *token);
  for (const auto& [id, token] : stray) leases_->releaseOrLetExpire(id, token);
}

}  // namespace penumbra::server
