// An image being rendered (GET /api/scenes/{id}/image): its ticket, scene and page, its progress
// (JobProgress: stage "tracing", then "sensors" with GI — sensors placed of at most one a pixel,
// so the fraction never overstates — then "shading" by rows, then "encoding") and how it ended.
// The renderer's progress callback (report) throws RenderCancelled once the job was cancelled —
// by DELETE of its ticket, a newer render from the same page, the server stopping — or its
// client closed the request. `seq`: its place among its page's renders (RenderJobs orders by it).
// Thread-safe.
#pragma once

#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>

#include "server/job_progress.h"

namespace penumbra::server {

class RenderCancelled : public std::runtime_error {
 public:
  explicit RenderCancelled(const std::string& why) : std::runtime_error(why) {}
};

class RenderJob {
 public:
  enum class State { Running, Done, Cancelled, Failed };

  // `clientGone`: whether the requesting client closed its connection (may be empty).
  RenderJob(std::string ticket, std::string sceneId, std::string page, std::optional<uint64_t> seq,
            std::function<bool()> clientGone);

  const std::string& ticket() const { return ticket_; }
  const std::string& sceneId() const { return sceneId_; }
  const std::string& page() const { return page_; }
  std::optional<uint64_t> seq() const { return seq_; }

  // The renderer's progress (rows done of total; with GI first sensors placed, total 0).
  void report(size_t done, size_t total);
  // A stage without a count (before the first row, encoding); checks for a cancel too.
  void stage(const char* name);
  // Asks the render to stop at its next report, saying why; returns at once.
  void cancel(const std::string& why);
  void end(State state);  // by the rendering request
  State state() const;
  bool ended() const { return state() != State::Running; }
  double endedSecondsAgo() const;
  uint64_t reports() const { return progress_.reports(); }

  // {"ticket", "scene", "page"?, "seq"?, "state": "running"|"done"|"cancelled"|"failed", "reason"?,
  // "progress": JobProgress::toJson}.
  nlohmann::json toJson() const;

  void setPixels(size_t pixels) { pixels_ = pixels; }

 private:
  void check();
  const std::string ticket_, sceneId_, page_;
  const std::optional<uint64_t> seq_;
  const std::function<bool()> clientGone_;
  size_t pixels_ = 0;  // the image's, bounding the sensors
  JobProgress progress_;
  mutable std::mutex mutex_;  // guards the fields below
  std::string reason_;
  State state_ = State::Running;
  double endedAt_ = 0;  // progress_.elapsedSeconds() when it ended
};

}  // namespace penumbra::server
