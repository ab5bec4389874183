// The threads that apply edit batches, one per core (docs/API.md "Load"). Reads take no lock
// (they serve immutable snapshots), but they share the cores with edits: with a batch applying
// on each scene's request thread, ten scenes edited at once meant ten relighting threads on two
// cores, and a 1 ms read waited behind them. Optionally (`serve --edit-nice K`) the workers
// also run K nice steps below the request threads, so that reads go first. Thread-safe.
#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace penumbra::server {

class EditWorkers {
 public:
  // `threads` workers (0 or less: one per core; at least 2, one kept for light work), each
  // `niceness` steps (0–19) below the priority of the thread that makes them. Linux lets any thread
  // lower its own priority (nice values are per thread); elsewhere the workers keep that priority.
  EditWorkers(int threads, int niceness);
  ~EditWorkers();  // lets the queued work finish, then joins
  EditWorkers(const EditWorkers&) = delete;
  EditWorkers& operator=(const EditWorkers&) = delete;

  // Runs `work` on a worker (in arrival order when all are busy) and returns once it ran;
  // rethrows what it threw. Heavy work (a frame relighting the whole scene: isHeavyFrame) runs on
  // at most all workers but one: the last is kept for light work, so that one user's heavy frames
  // cannot make other scenes' drags wait for them (two frames adding 22 lights each held both
  // workers and a 15 ms edit waited 44 s).
  void run(const std::function<void()>& work, bool heavy = false);

  int niceness() const { return niceness_; }
  size_t threads() const { return threads_.size(); }

 private:
  struct Job {
    const std::function<void()>* work;
    bool heavy = false;
    std::exception_ptr error;
    bool done = false;
  };
  void serve();
  std::deque<Job*>::iterator nextRunnable();  // the first queued job a worker may take now

  const int niceness_;
  std::mutex mutex_;
  std::condition_variable queued_;  // a job arrived, or stopping
  std::condition_variable done_;    // a job finished
  std::deque<Job*> jobs_;
  bool stopping_ = false;
  size_t heavyRunning_ = 0;
  size_t threadCount_ = 0;  // set before any thread starts
  std::vector<std::thread> threads_;
};

}  // namespace penumbra::server
