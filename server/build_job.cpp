#include "server/build_job.h"

namespace penumbra::server {

BuildJob::BuildJob(std::string id, std::string name, std::string ticket)
    : id_(std::move(id)), name_(std::move(name)), ticket_(std::move(ticket)) {}

void BuildJob::report(const char* stage, size_t done, size_t total) {
  record(stage, done, total);
  check();
}

void BuildJob::record(const char* stage, size_t done, size_t total) {
  std::lock_guard lock(mutex_);
  const Clock::time_point now = Clock::now();
  const bool sameStage = stage_ == stage;
  if (sameStage && done != total &&
      now - reported_ < std::chrono::milliseconds(1000 / kProgressPerSecond))
    return;
  if (!sameStage) stage_ = stage;
  done_ = done;
  total_ = total;
  reported_ = now;
}

EngineProgress BuildJob::progress() {
  return [this](const char* stage, size_t done, size_t total) { report(stage, done, total); };
}

void BuildJob::check() const {
  if (cancelled_) throw BuildCancelled();
}

void BuildJob::end() {
  std::lock_guard lock(mutex_);
  ended_ = true;
  endedChanged_.notify_all();
}

bool BuildJob::waitEnded(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  return endedChanged_.wait_for(lock, timeout, [this] { return ended_; });
}

nlohmann::json BuildJob::toJson() const {
  std::lock_guard lock(mutex_);
  nlohmann::json progress = {
      {"stage", stage_},
      {"done", done_},
      {"total", total_},
      {"fraction", total_ > 0 ? nlohmann::json(double(done_) / double(total_)) : nlohmann::json()},
      {"elapsed_seconds", std::chrono::duration<double>(Clock::now() - started_).count()},
      {"cancelling", cancelled_.load()}};
  nlohmann::json out = {{"id", id_}, {"name", name_}, {"state", "building"}};
  if (!ticket_.empty()) out["ticket"] = ticket_;
  out["progress"] = std::move(progress);
  return out;
}

}  // namespace penumbra::server
