// Scenes being created: reserved ids with a BuildJob each, built outside the lock, cancellable
// (DELETE of a building scene, the server stopping).
#include <chrono>

#include "core/geom/resource_limit.h"
#include "protocol/scene_json.h"
#include "server/api_errors.h"
#include "server/http_server.h"

namespace penumbra::server {

namespace {

// How long DELETE of a building scene waits for its build to stop (it stops at the engine's
// next report or beat: a few casts, vertices or cells of a receiver).
constexpr std::chrono::seconds kBuildCancelWait{30};

ApiError cancelledError() {
  return ApiError(409, error_code::kBuildCancelled, "",
                  "the build was cancelled (DELETE of the scene, or the server stopping)");
}

}  // namespace

std::string HttpServer::addScene(Scene scene, const std::string& name,
                                 const std::string& preferredId) {
  return buildScene(reserveBuild(name, preferredId.empty() ? name : preferredId), std::move(scene),
                    name);
}

std::shared_ptr<BuildJob> HttpServer::reserveBuild(const std::string& name,
                                                   const std::string& preferredId,
                                                   const std::string& ticket) {
  const std::string& preferred = preferredId.empty() ? name : preferredId;
  std::vector<std::string> elsewhere;  // ids other nodes hold: reserved until one is claimed
  auto freeElsewhere = [&] {
    std::lock_guard lock(scenesMutex_);
    for (const std::string& taken : elsewhere) scenes_.erase(taken);
  };
  for (;;) {
    std::string id;
    {
      std::lock_guard lock(scenesMutex_);
      if (scenes_.size() - elsewhere.size() >= options_.maxScenes) {
        for (const std::string& taken : elsewhere) scenes_.erase(taken);
        throw ApiError(429, error_code::kTooManyScenes, "",
                       "the server already holds " + std::to_string(options_.maxScenes) +
                           " scenes (--max-scenes); DELETE one first");
      }
      id = freshId(preferred);
      scenes_.emplace(id, nullptr);  // reserved while it builds
    }
    bool claimed = true;
    try {
      claimed = !leases_ || claimNewId(id);
    } catch (const std::exception& error) {
      elsewhere.push_back(id);
      freeElsewhere();
      throw ApiError(503, error_code::kJournalFailed, "",
                     std::string("the scene leases cannot be read: ") + error.what());
    }
    if (!claimed) {
      elsewhere.push_back(id);
      continue;
    }
    freeElsewhere();
    std::lock_guard lock(scenesMutex_);
    auto job = std::make_shared<BuildJob>(id, name, ticket);
    if (stopping_) job->cancel();
    builds_[id] = job;
    return job;
  }
}

void HttpServer::abandonBuild(BuildJob& job) {
  std::optional<int64_t> lease;
  {
    std::lock_guard lock(scenesMutex_);
    scenes_.erase(job.id());
    builds_.erase(job.id());
    if (const auto it = leaseTokens_.find(job.id()); it != leaseTokens_.end()) {
      lease = it->second;
      leaseTokens_.erase(it);
    }
  }
  if (lease) {
    leases_->releaseOrLetExpire(job.id(), *lease);
  }
  job.end();
}

std::string HttpServer::buildScene(const std::shared_ptr<BuildJob>& job, Scene scene,
                                   const std::string& name) {
  const std::string& id = job->id();
  // Build outside the lock: a large scene takes seconds and other scenes keep serving.
  std::shared_ptr<SceneSession> session;
  int64_t key = 0;
  try {
    job->check();
    // The journal keeps the scene as built (sceneFromJson(sceneToJson(s)) == s), committed
    // before the scene is served or acknowledged.
    const std::string source = journal_ ? protocol::sceneToJson(scene).dump() : "";
    session =
        std::make_shared<SceneSession>(id, name, std::move(scene), options_.engine, job->progress());
    job->check();  // last chance: once journaled, the scene is served (a DELETE then removes it)
    if (journal_) {
      try {
        LeaseToken lease;
        {
          std::lock_guard lock(scenesMutex_);
          if (const auto it = leaseTokens_.find(id); it != leaseTokens_.end()) lease = it->second;
        }
        key = journal_->addScene(id, name, source, session->snapshot()->version, lease);
      } catch (const std::exception& error) {
        throw ApiError(503, error_code::kJournalFailed, "",
                       std::string("the journal could not record the scene: ") + error.what());
      }
    }
  } catch (const BuildCancelled&) {
    session.reset();  // its memory before the id is free again
    abandonBuild(*job);
    throw cancelledError();
  } catch (...) {
    session.reset();
    abandonBuild(*job);
    throw;
  }
  {
    std::lock_guard lock(scenesMutex_);
    if (journal_) journalKeys_[session.get()] = key;
    if (leases_) lastUse_[id] = std::chrono::steady_clock::now();
    scenes_[id] = std::move(session);
    builds_.erase(id);
  }
  job->end();
  return id;
}

bool HttpServer::cancelBuild(const std::string& id) {
  std::shared_ptr<BuildJob> job;
  {
    std::lock_guard lock(scenesMutex_);
    const auto it = builds_.find(id);
    if (it == builds_.end()) return false;
    job = it->second;
  }
  job->cancel();
  if (!job->waitEnded(kBuildCancelWait))
    throw ApiError(503, error_code::kBuilding, "id",
                   "the build of scene '" + id + "' did not stop within " +
                       std::to_string(kBuildCancelWait.count()) + " s; it stops at its next step");
  return true;
}

std::vector<nlohmann::json> HttpServer::buildsJson() const {
  std::vector<std::shared_ptr<BuildJob>> jobs;
  {
    std::lock_guard lock(scenesMutex_);
    for (const auto& [id, job] : builds_) jobs.push_back(job);
  }
  std::vector<nlohmann::json> out;
  for (const auto& job : jobs) out.push_back(job->toJson());
  return out;
}

}  // namespace penumbra::server

namespace penumbra::server {

bool HttpServer::servesScene(const std::string& id) const {
  std::lock_guard lock(scenesMutex_);
  const auto it = scenes_.find(id);
  return it != scenes_.end() && it->second;
}

std::shared_ptr<BuildJob> HttpServer::findBuild(const std::string& id) const {
  std::lock_guard lock(scenesMutex_);
  const auto it = builds_.find(id);
  return it == builds_.end() ? nullptr : it->second;
}

}  // namespace penumbra::server
