// Loops over independent items on up to N threads (TBB): each item writes only its own outputs,
// so results are the same on any number of threads. Shared by the engine's build steps and the
// renderer's rows; forEach may be called from inside another forEach of the same object (nested
// loops share it).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cstddef>
#include <memory>

namespace penumbra {

// ThreadSanitizer cannot see the synchronisation inside Debian's libtbb (not instrumented): every
// join of a parallel_for would be reported as a race. A TSan build (the server tests, README
// "Fuzzing and the thread sanitizer") runs every loop on the calling thread; the loops' own
// independence is checked by tests giving the same bytes on 1 and 2 threads instead (ThreadCount.*,
// Renderer.OneAndTwoThreadsDrawTheSameBytes).
#if defined(__SANITIZE_THREAD__)
inline constexpr bool kLoopsOnOneThread = true;
#else
inline constexpr bool kLoopsOnOneThread = false;
#endif

class Parallel {
 public:
  // threads <= 0: every core TBB sees; 1: plain loops on the calling thread.
  explicit Parallel(int threads)
      : threads_(kLoopsOnOneThread ? 1 : threads > 0 ? threads : tbb::info::default_concurrency()),
        arena_(threads_ > 1 ? std::make_unique<tbb::task_arena>(threads_) : nullptr) {}

  int threads() const { return threads_; }

  // While one lives, loops started on the thread that made it run on that thread alone, whatever
  // their object's thread count: work on a low-priority thread (the server's heavy edit lane)
  // must not spread to TBB's shared workers, which run at everyone's priority. Not copyable.
  class OnThisThreadOnly {
   public:
    OnThisThreadOnly() : before_(onlyHere()) { onlyHere() = true; }
    ~OnThisThreadOnly() { onlyHere() = before_; }
    OnThisThreadOnly(const OnThisThreadOnly&) = delete;
    OnThisThreadOnly& operator=(const OnThisThreadOnly&) = delete;

   private:
    bool before_;
  };

  // body(i) for every i in [0, n), in any order and concurrently; items are handed out `grain`
  // at a time. Exceptions propagate to the caller (the first one thrown).
  template <class Body>
  void forEach(size_t n, const Body& body, size_t grain = 1) const {
    if (!arena_ || n <= 1 || onlyHere()) {
      for (size_t i = 0; i < n; ++i) body(i);
      return;
    }
    arena_->execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) body(i);
      });
    });
  }

 private:
  static bool& onlyHere() {
    thread_local bool only = false;
    return only;
  }

  int threads_;
  std::unique_ptr<tbb::task_arena> arena_;  // pointer: the engine stays movable
};

}  // namespace penumbra
