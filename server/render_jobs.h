// The renders running now, and those ended in the last kKeepEndedSeconds (so a poll or an event
// stream sees how one ended), by ticket. Starting a render with a page label cancels that page's
// running renders (a newer view supersedes them). Thread-safe.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "server/render_job.h"

namespace penumbra::server {

class RenderJobs {
 public:
  // A new running job; `ticket` empty: one is made up. Throws ApiError 409 when `ticket` names
  // a render still running.
  std::shared_ptr<RenderJob> start(const std::string& sceneId, std::string ticket,
                                   const std::string& page, std::function<bool()> clientGone);
  // The job with this ticket on this scene (running or recently ended); null when none.
  std::shared_ptr<RenderJob> find(const std::string& sceneId, const std::string& ticket) const;
  // The scene's jobs, running and recently ended, by ticket.
  std::vector<std::shared_ptr<RenderJob>> ofScene(const std::string& sceneId) const;
  void cancelAll(const std::string& why);
  // Cancels the running renders started with this page label (none when it is empty).
  void cancelPage(const std::string& page);

  static constexpr double kKeepEndedSeconds = 10;
  static constexpr size_t kKeepEnded = 64;

 private:
  void prune();  // call with mutex_ held
  void cancelPageLocked(const std::string& page);  // call with mutex_ held
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<RenderJob>> jobs_;  // by ticket
  uint64_t next_ = 1;
};

}  // namespace penumbra::server
