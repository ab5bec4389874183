#include "cli/progress_bar.h"

#include <unistd.h>

#include <cstdio>

namespace penumbra::cli {

ProgressBar::ProgressBar(std::string label)
    : label_(std::move(label)), terminal_(isatty(STDERR_FILENO)), start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(size_t done, size_t total) {
  total_ = total;
  const int percent = total ? int(100 * done / total) : 100;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (terminal_) {
    if (percent == lastShown_) return;
    lastShown_ = percent;
    const int width = 30, filled = percent * width / 100;
    std::fprintf(stderr, "\r%s [%.*s%*s] %3d%% %zu/%zu %.1fs", label_.c_str(), filled,
                 "##############################", width - filled, "", percent, done, total, seconds);
  } else {
    if (percent / 10 == lastShown_) return;
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

}  // namespace penumbra::cli
