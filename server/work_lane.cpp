#include "server/work_lane.h"

#include <algorithm>
#include <cerrno>
#include <optional>

#include "core/util/parallel.h"

#if defined(__linux__)
#include <sys/resource.h>
#include <unistd.h>
#endif

namespace penumbra::server {

namespace {

// Lowers the calling thread's CPU priority by `steps` (Linux: nice values are per thread).
void lowerOwnPriority(int steps) {
#if defined(__linux__)
  if (steps <= 0) return;
  const id_t self = id_t(gettid());
  errno = 0;
  const int now = getpriority(PRIO_PROCESS, self);
  if (errno == 0) setpriority(PRIO_PROCESS, self, std::min(19, now + steps));
#else
  (void)steps;
#endif
}

}  // namespace

WorkLane::WorkLane(int threads, int niceness, bool loopsOnItsThreads)
    : niceness_(std::clamp(niceness, 0, 19)), loopsOnItsThreads_(loopsOnItsThreads) {
  for (int i = 0; i < std::max(1, threads); ++i) threads_.emplace_back([this] { serve(); });
}

WorkLane::~WorkLane() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  queuedOrStopping_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

void WorkLane::run(const std::function<void()>& work) {
  Job job{&work, nullptr, false};
  std::unique_lock lock(mutex_);
  jobs_.push_back(&job);
  queuedOrStopping_.notify_one();
  done_.wait(lock, [&] { return job.done; });
  if (job.error) std::rethrow_exception(job.error);
}

size_t WorkLane::queued() const {
  std::lock_guard lock(mutex_);
  return jobs_.size();
}

void WorkLane::serve() {
  lowerOwnPriority(niceness_);
  std::optional<Parallel::OnThisThreadOnly> loopsHere;
  if (loopsOnItsThreads_) loopsHere.emplace();
  std::unique_lock lock(mutex_);
  for (;;) {
    queuedOrStopping_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
    if (jobs_.empty()) return;  // stopping, nothing left
    Job* job = jobs_.front();
    jobs_.pop_front();
    lock.unlock();
    try {
      (*job->work)();
    } catch (...) {
      job->error = std::current_exception();
    }
    lock.lock();
    job->done = true;
    done_.notify_all();
  }
}

}  // namespace penumbra::server
