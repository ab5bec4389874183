// The renders running now, and those ended in the last kKeepEndedSeconds (so a poll or an event
// stream sees how one ended), by ticket. Starting a render with a page label cancels that page's
// running renders (a newer view supersedes them). A page that numbers its renders (`seq`, counting
// up) is ordered by the numbers, not by arrival: a render that arrives after one with a higher
// number of its page started (its request overtaken on the way) is refused, and stops nothing.
// Thread-safe.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "server/render_job.h"

namespace penumbra::server {

class RenderJobs {
 public:
  // A new running job; `ticket` empty: one is made up. Throws ApiError 409 when `ticket` names
  // a render still running, or (render_cancelled) when the page's renders went past `seq`.
  // Cancels the page's running renders with a lower `seq` (all of them when either has none).
  std::shared_ptr<RenderJob> start(const std::string& sceneId, std::string ticket,
                                   const std::string& page, std::optional<uint64_t> seq,
                                   std::function<bool()> clientGone);
  // The job with this ticket on this scene (running or recently ended); null when none.
  std::shared_ptr<RenderJob> find(const std::string& sceneId, const std::string& ticket) const;
  // The scene's jobs, running and recently ended, by ticket.
  std::vector<std::shared_ptr<RenderJob>> ofScene(const std::string& sceneId) const;
  void cancelAll(const std::string& why);
  // What start does to the page's other renders, before the new one waits for its memory:
  // cancels those it replaces, or throws 409 render_cancelled when it is out of date (nothing
  // when `page` is empty).
  void supersede(const std::string& page, std::optional<uint64_t> seq);

  static constexpr double kKeepEndedSeconds = 10;
  static constexpr size_t kKeepEnded = 64;

 private:
  void prune();  // call with mutex_ held
  void supersedeLocked(const std::string& page, std::optional<uint64_t> seq);  // mutex_ held
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<RenderJob>> jobs_;  // by ticket
  uint64_t next_ = 1;
};

}  // namespace penumbra::server
