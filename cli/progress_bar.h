// A progress bar on stderr for long CLI runs: redrawn in place on a terminal,
// a line per 10% otherwise (logs, CI). Used from one thread at a time.
#pragma once

#include <chrono>
#include <string>

#include "core/util/shared_progress.h"

namespace penumbra::cli {

class ProgressBar {
 public:
  // A bar with `quietSeconds` > 0 shows nothing until that long after its first update: a step
  // that is brief on most scenes stays out of the output, and shows where it is not.
  explicit ProgressBar(std::string label, double quietSeconds = 0);
  ~ProgressBar();
  void update(size_t done, size_t total);
  void finish();

 private:
  std::string label_;
  bool terminal_;
  bool finished_ = false;
  int lastShown_ = -1;  // percent (terminal) or tenth (log) last printed
  std::chrono::steady_clock::time_point start_;
  double quietSeconds_;
  std::chrono::steady_clock::time_point firstUpdate_{};
  bool updated_ = false;
  size_t total_ = 0;
};

// An engine build's progress: its long steps "casting" and "illumination" (they run at once)
// as two bars; the steps before them (ordering, cube, receivers: brief on rooms, seconds on a
// scanned model of 70 k triangles) only where one lasts past half a second.
class BuildBars {
 public:
  StepProgress progress();
  void finish();

 private:
  static constexpr double kBriefSeconds = 0.5;
  ProgressBar ordering_{"ordering", kBriefSeconds}, cube_{"cube", kBriefSeconds},
      receivers_{"receivers", kBriefSeconds};
  ProgressBar casting_{"casting"}, illumination_{"illumination"};
};

}  // namespace penumbra::cli
