// A journaled scene being restored (at start, or taken over on a request): a BuildJob for its
// progress and cancel flag (the engine's reports and the replay's frames throw BuildCancelled once
// cancelled), and how the restore ended. A DELETE cancels it asking for the scene's removal: the
// restoring thread, which holds the scene's journal key (and lease), removes the rows before it
// frees the id, and the DELETE waits for that; a stop cancels it leaving the journal as it was.
// Thread-safe.
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <string>

#include "server/build_job.h"

namespace penumbra::server {

class RestoreJob {
 public:
  explicit RestoreJob(const std::string& id) : build_(id, id, "") {}

  BuildJob& build() { return build_; }
  EngineProgress progress() { return build_.progress(); }

  // A stop: the restore ends at its next report, the journal untouched.
  void cancel() { build_.cancel(); }
  // A DELETE: the restore ends at its next report and the scene leaves the journal.
  void cancelAndDelete() {
    deleteWanted_ = true;
    build_.cancel();
  }
  bool deleteWanted() const { return deleteWanted_; }

  // How the restoring thread left the scene: served (it finished first), or not served and then
  // removed from the journal (`deleted`) or not (`problem`: why a wanted removal failed).
  struct Ended {
    bool served = false;
    bool deleted = false;
    std::string problem;
  };
  // The restoring thread, once: records how it ended and wakes the waiters.
  void end(Ended ended) {
    {
      std::lock_guard lock(mutex_);
      ended_ = std::move(ended);
    }
    build_.end();
  }
  // How it ended; nullopt when it did not within `timeout`.
  std::optional<Ended> waitEnded(std::chrono::milliseconds timeout) {
    if (!build_.waitEnded(timeout)) return std::nullopt;
    std::lock_guard lock(mutex_);
    return ended_;
  }

 private:
  BuildJob build_;
  std::atomic<bool> deleteWanted_{false};
  std::mutex mutex_;  // guards ended_
  Ended ended_;
};

}  // namespace penumbra::server
