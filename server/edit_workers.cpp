#include "server/edit_workers.h"

#include <algorithm>
#include <cerrno>
#include <optional>

#include "core/engine/parallel.h"

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

EditWorkers::EditWorkers(int threads, int niceness, int heavyNiceness)
    : niceness_(std::clamp(niceness, 0, 19)),
      heavyNiceness_(std::clamp(niceness_ + std::max(0, heavyNiceness), 0, 19)) {
  if (threads <= 0) threads = int(std::thread::hardware_concurrency());
  threads = std::max(1, threads);
  for (int i = 0; i < threads; ++i)
    threads_.emplace_back([this] { serve(light_, niceness_, false); });
  threads_.emplace_back([this] { serve(heavy_, heavyNiceness_, true); });
}

EditWorkers::~EditWorkers() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  light_.queued.notify_all();
  heavy_.queued.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

void EditWorkers::run(const std::function<void()>& work, bool heavy) {
  Job job{&work, nullptr, false};
  Lane& lane = heavy ? heavy_ : light_;
  std::unique_lock lock(mutex_);
  lane.jobs.push_back(&job);
  lane.queued.notify_one();
  done_.wait(lock, [&] { return job.done; });
  if (job.error) std::rethrow_exception(job.error);
}

size_t EditWorkers::heavyQueued() const {
  std::lock_guard lock(mutex_);
  return heavy_.jobs.size();
}

void EditWorkers::serve(Lane& lane, int niceness, bool loopsHere) {
  lowerOwnPriority(niceness);
  // The heavy lane's engine loops stay on this thread, at its priority (TBB's shared workers
  // run at everyone's).
  std::optional<Parallel::OnThisThreadOnly> oneCore;
  if (loopsHere) oneCore.emplace();
  std::unique_lock lock(mutex_);
  for (;;) {
    lane.queued.wait(lock, [&] { return stopping_ || !lane.jobs.empty(); });
    if (lane.jobs.empty()) return;  // stopping, nothing left
    Job* job = lane.jobs.front();
    lane.jobs.pop_front();
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
