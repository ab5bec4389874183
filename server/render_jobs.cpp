#include "server/render_jobs.h"

#include <algorithm>

#include "server/api_errors.h"

namespace penumbra::server {

std::shared_ptr<RenderJob> RenderJobs::start(const std::string& sceneId, std::string ticket,
                                             const std::string& page, std::optional<uint64_t> seq,
                                             std::function<bool()> clientGone) {
  std::lock_guard lock(mutex_);
  prune();
  if (ticket.empty()) {
    do ticket = std::string("r").append(std::to_string(next_++));
    while (jobs_.count(ticket));
  }
  if (const auto it = jobs_.find(ticket); it != jobs_.end() && !it->second->ended())
    throw ApiError(409, error_code::kBadParameter, "query.ticket",
                   "a render with ticket '" + ticket + "' is still running");
  supersedeLocked(page, seq);
  auto job = std::make_shared<RenderJob>(ticket, sceneId, page, seq, std::move(clientGone));
  jobs_[ticket] = job;
  return job;
}

std::shared_ptr<RenderJob> RenderJobs::find(const std::string& sceneId,
                                            const std::string& ticket) const {
  std::lock_guard lock(mutex_);
  const auto it = jobs_.find(ticket);
  return it != jobs_.end() && it->second->sceneId() == sceneId ? it->second : nullptr;
}

std::vector<std::shared_ptr<RenderJob>> RenderJobs::ofScene(const std::string& sceneId) const {
  std::lock_guard lock(mutex_);
  std::vector<std::shared_ptr<RenderJob>> out;
  for (const auto& [ticket, job] : jobs_)
    if (job->sceneId() == sceneId && job->endedSecondsAgo() <= kKeepEndedSeconds)
      out.push_back(job);
  return out;
}

void RenderJobs::cancelAll(const std::string& why) {
  std::lock_guard lock(mutex_);
  for (auto& [ticket, job] : jobs_) job->cancel(why);
}

void RenderJobs::supersede(const std::string& page, std::optional<uint64_t> seq) {
  std::lock_guard lock(mutex_);
  supersedeLocked(page, seq);
}

void RenderJobs::supersedeLocked(const std::string& page, std::optional<uint64_t> seq) {
  if (page.empty()) return;
  // Overtaken on its way (sent just before its client aborted it, it reached us after the render
  // that replaced it): it must not stop that one.
  if (seq)
    for (const auto& [ticket, job] : jobs_)
      if (job->page() == page && job->seq() && *job->seq() >= *seq)
        throw ApiError(409, error_code::kRenderCancelled, "query.seq",
                       "the render was cancelled: render " + std::to_string(*job->seq()) +
                           " of page '" + page + "' (ticket '" + ticket +
                           "') started before it, so it is out of date");
  for (auto& [ticket, job] : jobs_)
    if (job->page() == page && !job->ended() && (!seq || !job->seq() || *job->seq() < *seq))
      job->cancel("a newer render from the same page");
}

void RenderJobs::prune() {
  std::vector<std::pair<double, std::string>> ended;
  for (auto it = jobs_.begin(); it != jobs_.end();) {
    if (it->second->ended() && it->second->endedSecondsAgo() > kKeepEndedSeconds) {
      it = jobs_.erase(it);
    } else {
      if (it->second->ended()) ended.emplace_back(it->second->endedSecondsAgo(), it->first);
      ++it;
    }
  }
  if (ended.size() <= kKeepEnded) return;
  std::sort(ended.begin(), ended.end());  // the most recently ended first
  for (size_t i = kKeepEnded; i < ended.size(); ++i) jobs_.erase(ended[i].second);
}

}  // namespace penumbra::server
