#include "cli/progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

namespace penumbra::cli {

ProgressBar::ProgressBar(std::string label, double quietSeconds)
    : label_(std::move(label)),
      terminal_(isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      quietSeconds_(quietSeconds) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(size_t done, size_t total) {
  total_ = total;
  const auto now = std::chrono::steady_clock::now();
  if (!updated_) firstUpdate_ = now, updated_ = true;
  if (std::chrono::duration<double>(now - firstUpdate_).count() < quietSeconds_) return;
  const int percent = total ? int(100 * std::min(done, total) / total) : 0;  // a total may grow
  const double seconds = std::chrono::duration<double>(now - start_).count();
  if (terminal_) {
    if (percent == lastShown_) return;
    lastShown_ = percent;
    const int width = 30, filled = percent * width / 100;
    std::fprintf(stderr, "\r%s [%.*s%*s] %3d%% %zu/%zu %.1fs", label_.c_str(), filled,
                 "##############################", width - filled, "", percent, done, total, seconds);
  } else {
    if (percent / 10 <= lastShown_) return;  // a log shows tenths rising, not a grown total's dips
    lastShown_ = percent / 10;
    std::fprintf(stderr, "%s: %d%% (%zu/%zu) %.1fs\n", label_.c_str(), percent, done, total, seconds);
  }
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (finished_) return;
  finished_ = true;
  if (terminal_ && lastShown_ >= 0) std::fprintf(stderr, "\n");
}

StepProgress BuildBars::progress() {
  // The first three run one after another: each ends its line when the next one starts.
  return [this](const char* step, size_t done, size_t total) {
    if (std::strcmp(step, "ordering") == 0) ordering_.update(done, total);
    if (std::strcmp(step, "cube") == 0) ordering_.finish(), cube_.update(done, total);
    if (std::strcmp(step, "receivers") == 0) cube_.finish(), receivers_.update(done, total);
    if (std::strcmp(step, "casting") == 0) receivers_.finish(), casting_.update(done, total);
    if (std::strcmp(step, "illumination") == 0) receivers_.finish(), illumination_.update(done, total);
  };
}

void BuildBars::finish() {
  for (ProgressBar* bar : {&ordering_, &cube_, &receivers_, &casting_, &illumination_}) bar->finish();
}

}  // namespace penumbra::cli
