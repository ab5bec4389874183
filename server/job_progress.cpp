#include "server/job_progress.h"

namespace penumbra::server {

bool JobProgress::record(const char* stage, size_t done, size_t total) {
  std::lock_guard lock(mutex_);
  const Clock::time_point now = Clock::now();
  const bool sameStage = stage_ == stage;
  if (sameStage && done != total && now - reported_ < std::chrono::milliseconds(1000 / kPerSecond))
    return false;
  if (!sameStage) stage_ = stage;
  done_ = done;
  total_ = total;
  reported_ = now;
  ++reports_;
  return true;
}

double JobProgress::elapsedSeconds() const {
  return std::chrono::duration<double>(Clock::now() - started_).count();
}

nlohmann::json JobProgress::toJson() const {
  std::lock_guard lock(mutex_);
  return {
      {"stage", stage_},
      {"done", done_},
      {"total", total_},
      {"fraction", total_ > 0 ? nlohmann::json(double(done_) / double(total_)) : nlohmann::json()},
      {"elapsed_seconds", elapsedSeconds()},
      {"cancelling", cancelled_.load()}};
}

}  // namespace penumbra::server
