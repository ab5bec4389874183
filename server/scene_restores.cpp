// Scenes being restored from the journal as cancellable jobs (server/restore_job.h): a DELETE of a
// restoring scene cancels its restore and the restoring thread removes it from the journal; a stop
// cancels every restore and leaves the journal as it was.
#include <chrono>

#include "server/api_errors.h"
#include "server/http_server.h"

namespace penumbra::server {

namespace {

// How long a DELETE of a restoring scene waits for the restore to stop (it stops at the engine's
// next report, or before the next journaled frame: one frame's work at most).
constexpr std::chrono::seconds kRestoreCancelWait{30};

}  // namespace

std::optional<RestoreJob::Ended> HttpServer::cancelRestore(const std::string& id) {
  std::shared_ptr<RestoreJob> job;
  {
    std::lock_guard lock(scenesMutex_);
    const auto it = restoring_.find(id);
    if (it == restoring_.end()) return std::nullopt;
    job = it->second;
  }
  job->cancelAndDelete();
  std::optional<RestoreJob::Ended> ended = job->waitEnded(kRestoreCancelWait);
  if (!ended)
    throw ApiError(503, error_code::kRestoring, "id",
                   "the restore of scene '" + id + "' did not stop within " +
                       std::to_string(kRestoreCancelWait.count()) + " s; it stops at its next step");
  return ended;
}

RestoreJob::Ended HttpServer::dropCancelledRestore(const std::string& id,
                                                   std::optional<int64_t> key,
                                                   const RestoreJob& job) {
  RestoreJob::Ended ended;
  if (!job.deleteWanted() || !journal_) return ended;  // a stop: the journal as it was
  if (!key) {  // cancelled before its rows were read: nothing of it here to remove
    ended.problem = "its journal rows were not read yet";
    return ended;
  }
  try {
    journal_->removeScene(*key);  // under the lease this thread still holds
  } catch (const std::exception& error) {
    ended.problem = error.what();
    return ended;
  }
  removeUploadsOf(id);  // the journal no longer names them
  std::optional<int64_t> lease;  // given back, as a DELETE does
  {
    std::lock_guard lock(scenesMutex_);
    if (const auto it = leaseTokens_.find(id); it != leaseTokens_.end()) {
      lease = it->second;
      leaseTokens_.erase(it);
    }
    lastUse_.erase(id);
  }
  if (lease) {
    leases_->releaseOrLetExpire(id, *lease);
  }
  ended.deleted = true;
  return ended;
}

}  // namespace penumbra::server
