#include "server/render_job.h"

namespace penumbra::server {

RenderJob::RenderJob(std::string ticket, std::string sceneId, std::string page,
                     std::optional<uint64_t> seq, std::function<bool()> clientGone)
    : ticket_(std::move(ticket)),
      sceneId_(std::move(sceneId)),
      page_(std::move(page)),
      seq_(seq),
      clientGone_(std::move(clientGone)) {
  progress_.record("tracing", 0, 0);
}

void RenderJob::report(size_t done, size_t total) {
  if (total == 0)
    progress_.record("sensors", done, std::max(pixels_, done));
  else
    progress_.record("shading", done, total);
  check();
}

void RenderJob::stage(const char* name) {
  progress_.record(name, 0, 0);
  check();
}

void RenderJob::check() {
  if (!progress_.cancelled() && clientGone_ && clientGone_())
    cancel("the client closed the request");
  if (progress_.cancelled()) {
    std::lock_guard lock(mutex_);
    throw RenderCancelled(reason_);
  }
}

void RenderJob::cancel(const std::string& why) {
  std::lock_guard lock(mutex_);
  if (state_ != State::Running || progress_.cancelled()) return;
  reason_ = why;
  progress_.cancel();
}

void RenderJob::end(State state) {
  std::lock_guard lock(mutex_);
  state_ = state;
  endedAt_ = progress_.elapsedSeconds();
}

RenderJob::State RenderJob::state() const {
  std::lock_guard lock(mutex_);
  return state_;
}

double RenderJob::endedSecondsAgo() const {
  std::lock_guard lock(mutex_);
  return state_ == State::Running ? 0 : progress_.elapsedSeconds() - endedAt_;
}

nlohmann::json RenderJob::toJson() const {
  static const char* const kStates[] = {"running", "done", "cancelled", "failed"};
  nlohmann::json out = {{"ticket", ticket_}, {"scene", sceneId_}};
  if (!page_.empty()) out["page"] = page_;
  if (seq_) out["seq"] = *seq_;
  std::lock_guard lock(mutex_);
  out["state"] = kStates[int(state_)];
  if (!reason_.empty()) out["reason"] = reason_;
  out["progress"] = progress_.toJson();
  if (state_ != State::Running) out["progress"]["elapsed_seconds"] = endedAt_;
  return out;
}

}  // namespace penumbra::server
