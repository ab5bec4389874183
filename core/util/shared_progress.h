// A long step's progress, counted from several threads and reported to one callback as
// (step name, done, total). The callback runs on one thread at a time, with `done` rising;
// add(), grow() and beat() may be called from any thread. A step whose size is found as it runs
// (the vertices to light, known receiver by receiver) grows its total.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <mutex>

namespace penumbra {

// Called with (step name, done, total) as a long step proceeds; may be empty.
using StepProgress = std::function<void(const char* step, size_t done, size_t total)>;

// Reports about every `every` items (and at the start and the end). Steps that run at once share
// one mutex (`shared`), so the callback stays on one thread at a time across them.
class SharedProgress {
 public:
  SharedProgress(const StepProgress& progress, const char* step, size_t total, size_t every,
                 std::mutex* shared = nullptr)
      : progress_(progress),
        step_(step),
        total_(total),
        every_(every),
        mutex_(shared ? *shared : own_) {
    if (progress_) progress_(step_, 0, total_);
  }
  void add(size_t items) {
    if (!progress_ || !items) return;
    const size_t done = done_.fetch_add(items) + items;
    if (done / every_ == (done - items) / every_ || done == total_) return;
    std::lock_guard lock(mutex_);
    if (done > reported_) progress_(step_, reported_ = done, total_);
  }
  // `items` more to do: reported with the next count.
  void grow(size_t items) { total_ += items; }
  // The same count again, from inside one long item (a model's shadow merged into the floor, a
  // big receiver's meshing), so the callback sees the work go on (and may throw to end it).
  void beat() {
    if (!progress_) return;
    std::lock_guard lock(mutex_);
    progress_(step_, reported_, total_);
  }
  void finish() {
    std::lock_guard lock(mutex_);
    if (progress_) progress_(step_, total_, total_);
  }

 private:
  const StepProgress& progress_;
  const char* step_;
  std::atomic<size_t> total_;
  size_t every_;
  std::atomic<size_t> done_{0};
  std::mutex own_;
  std::mutex& mutex_;
  size_t reported_ = 0;
};

}  // namespace penumbra
