// A scene being created (POST /api/scenes, HttpServer::addScene): its stage, done/total and
// elapsed seconds as the import and the engine report them, and a cancel flag. The engine's
// progress callback (report) throws BuildCancelled once the job is cancelled, so the build
// unwinds at its next report; the creating request catches it. Thread-safe.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "core/engine/engine.h"
#include "server/job_progress.h"

namespace penumbra::server {

// Thrown by BuildJob::report in a cancelled job's build (through the engine's parallel loops).
class BuildCancelled : public std::runtime_error {
 public:
  BuildCancelled() : std::runtime_error("the build was cancelled") {}
};

class BuildJob {
 public:
  // `ticket`: the creating client's own label for the job (may be empty), so it finds its build
  // in the scene list before it knows the id.
  BuildJob(std::string id, std::string name, std::string ticket);

  const std::string& id() const { return id_; }

  // The engine's progress callback: records the stage and its done/total (JobProgress::record),
  // then throws BuildCancelled when the job was cancelled.
  void report(const char* stage, size_t done, size_t total);
  EngineProgress progress();  // report() as an EngineProgress
  // Records a stage without a count (an import), without checking for a cancel.
  void note(const char* stage) { progress_.record(stage, 0, 0); }
  // Throws BuildCancelled when cancelled (between steps the engine does not report).
  void check() const;

  // Asks the build to stop at its next report; returns at once.
  void cancel() { progress_.cancel(); }
  bool cancelled() const { return progress_.cancelled(); }

  // The creating request marks the job ended (built, failed or cancelled); waitEnded returns
  // then, or after `timeout` (false).
  void end();
  bool waitEnded(std::chrono::milliseconds timeout);

  // {"id", "name", "state": "building", "ticket"?, "progress": JobProgress::toJson}.
  nlohmann::json toJson() const;

 private:
  const std::string id_, name_, ticket_;
  JobProgress progress_;
  std::mutex mutex_;  // guards ended_
  std::condition_variable endedChanged_;
  bool ended_ = false;
};

}  // namespace penumbra::server
