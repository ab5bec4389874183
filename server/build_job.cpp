#include "server/build_job.h"

namespace penumbra::server {

BuildJob::BuildJob(std::string id, std::string name, std::string ticket)
    : id_(std::move(id)), name_(std::move(name)), ticket_(std::move(ticket)) {}

void BuildJob::report(const char* stage, size_t done, size_t total) {
  progress_.record(stage, done, total);
  check();
}

EngineProgress BuildJob::progress() {
  return [this](const char* stage, size_t done, size_t total) { report(stage, done, total); };
}

void BuildJob::check() const {
  if (progress_.cancelled()) throw BuildCancelled();
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
  nlohmann::json out = {{"id", id_}, {"name", name_}, {"state", "building"}};
  if (!ticket_.empty()) out["ticket"] = ticket_;
  out["progress"] = progress_.toJson();
  return out;
}

}  // namespace penumbra::server
