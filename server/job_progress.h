// How far a long piece of work (a scene's build, an image's render) has come: its stage, that
// stage's done/total, the seconds since it started, and a cancel flag the work checks at its
// reports. Used by BuildJob and RenderJob. Thread-safe.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>

namespace penumbra::server {

class JobProgress {
 public:
  // Records the stage and its done/total: a new stage or a stage's end at once, else at most
  // kPerSecond times a second. Returns whether it recorded.
  bool record(const char* stage, size_t done, size_t total);

  void cancel() { cancelled_ = true; }
  bool cancelled() const { return cancelled_; }
  double elapsedSeconds() const;
  // Bumped by every recorded report: a watcher sends an update when it changed.
  uint64_t reports() const { return reports_; }

  // {"stage", "done", "total", "fraction" (null when the stage has no count),
  // "elapsed_seconds", "cancelling"}.
  nlohmann::json toJson() const;

  static constexpr int kPerSecond = 10;

 private:
  using Clock = std::chrono::steady_clock;
  const Clock::time_point started_ = Clock::now();
  std::atomic<bool> cancelled_{false};
  std::atomic<uint64_t> reports_{0};
  mutable std::mutex mutex_;  // guards the fields below
  std::string stage_ = "queued";
  size_t done_ = 0, total_ = 0;
  Clock::time_point reported_ = started_;
};

}  // namespace penumbra::server
