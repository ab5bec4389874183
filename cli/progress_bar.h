// A progress bar on stderr for long CLI runs: redrawn in place on a terminal,
// a line per 10% otherwise (logs, CI). Used from one thread at a time.
#pragma once

#include <chrono>
#include <string>

#include "core/util/shared_progress.h"

namespace penumbra::cli {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  ~ProgressBar();
  void update(size_t done, size_t total);
  void finish();

 private:
  std::string label_;
  bool terminal_;
  bool finished_ = false;
  int lastShown_ = -1;  // percent (terminal) or tenth (log) last printed
  std::chrono::steady_clock::time_point start_;
  size_t total_ = 0;
};

// An engine build's progress as two bars, its long steps "casting" and "illumination" (they
// run at once); the brief ones (ordering, cube, receivers) are not shown.
class BuildBars {
 public:
  StepProgress progress();
  void finish();

 private:
  ProgressBar casting_{"casting"}, illumination_{"illumination"};
};

}  // namespace penumbra::cli
