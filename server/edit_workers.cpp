#include "server/edit_workers.h"

#include <algorithm>
#include <cerrno>

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

EditWorkers::EditWorkers(int threads, int niceness) : niceness_(std::clamp(niceness, 0, 19)) {
  if (threads <= 0) threads = int(std::thread::hardware_concurrency());
  threads = std::max(2, threads);
  threadCount_ = size_t(threads);
  for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { serve(); });
}

EditWorkers::~EditWorkers() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  queued_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

void EditWorkers::run(const std::function<void()>& work, bool heavy) {
  Job job{&work, heavy, nullptr, false};
  std::unique_lock lock(mutex_);
  jobs_.push_back(&job);
  queued_.notify_all();  // the worker that may take it (a light job: the one kept for light work)
  done_.wait(lock, [&] { return job.done; });
  if (job.error) std::rethrow_exception(job.error);
}

std::deque<EditWorkers::Job*>::iterator EditWorkers::nextRunnable() {
  const bool heavyAllowed = heavyRunning_ + 1 < threadCount_;
  return std::find_if(jobs_.begin(), jobs_.end(),
                      [heavyAllowed](const Job* job) { return heavyAllowed || !job->heavy; });
}

void EditWorkers::serve() {
  lowerOwnPriority(niceness_);
  std::unique_lock lock(mutex_);
  for (;;) {
    queued_.wait(lock,
                 [this] { return (stopping_ && jobs_.empty()) || nextRunnable() != jobs_.end(); });
    if (jobs_.empty()) return;  // stopping, nothing left
    const auto next = nextRunnable();
    Job* job = *next;
    jobs_.erase(next);
    if (job->heavy) ++heavyRunning_;
    lock.unlock();
    try {
      (*job->work)();
    } catch (...) {
      job->error = std::current_exception();
    }
    lock.lock();
    if (job->heavy) {
      --heavyRunning_;
      queued_.notify_all();  // a heavy job waiting for a slot may start
    }
    job->done = true;
    done_.notify_all();
  }
}

}  // namespace penumbra::server
