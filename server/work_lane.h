// Threads at one CPU priority serving a queue of work in arrival order: the edit workers' light
// and heavy lanes (server/edit_workers.h) and the costly images' lane. Each thread lowers its own
// priority when it starts (Linux nice values are per thread; lowering needs no privilege, and it
// can never be raised back, hence threads kept for one priority); a lane that keeps loops on its
// threads runs their engine and render loops there alone (Parallel::OnThisThreadOnly), since TBB's
// shared workers run at everyone's priority. Thread-safe.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace penumbra::server {

class WorkLane {
 public:
  // `threads` threads (at least 1), each `niceness` steps (0–19) below the priority of the
  // thread that makes the lane.
  WorkLane(int threads, int niceness, bool loopsOnItsThreads);
  ~WorkLane();  // lets the queued work finish, then joins
  WorkLane(const WorkLane&) = delete;
  WorkLane& operator=(const WorkLane&) = delete;

  // Runs `work` on one of the lane's threads (in arrival order when all are busy) and returns
  // once it ran; rethrows what it threw.
  void run(const std::function<void()>& work);

  int niceness() const { return niceness_; }
  size_t threads() const { return threads_.size(); }
  size_t queued() const;  // waiting for a thread (those running not counted)

 private:
  struct Job {
    const std::function<void()>* work;
    std::exception_ptr error;
    bool done = false;
  };
  void serve();

  const int niceness_;
  const bool loopsOnItsThreads_;
  mutable std::mutex mutex_;
  std::condition_variable queuedOrStopping_, done_;
  std::deque<Job*> jobs_;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace penumbra::server
