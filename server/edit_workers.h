// The threads that apply edit batches (docs/API.md "Load"): one per core for light work, and one
// heavy lane below them for frames whose work grows with the whole scene. Reads take no lock
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
  // `threads` light workers (0 or less: one per core), each `niceness` steps (0–19) below the
  // priority of the thread that makes them, and one heavy-lane thread `heavyNiceness` steps
  // further below (at most 19 in all). Linux lets any thread lower its own priority (nice values
  // are per thread); elsewhere the workers keep that priority.
  EditWorkers(int threads, int niceness, int heavyNiceness);
  ~EditWorkers();  // lets the queued work finish, then joins
  EditWorkers(const EditWorkers&) = delete;
  EditWorkers& operator=(const EditWorkers&) = delete;

  // Runs `work` on a worker (in arrival order when all are busy) and returns once it ran;
  // rethrows what it threw. Heavy work (a frame relighting the whole scene: isHeavyFrame) runs
  // on the heavy lane only: one job at a time, below the light workers' priority, its engine loops
  // on that one thread (Parallel::OnThisThreadOnly), so one user's heavy frames take at most one
  // core and what is left of it, and light work never queues behind them (two frames adding 22
  // lights each had held both workers and another scene's 15 ms edit waited 44 s; a 20-light
  // frame beside image renders had put another client's drag p99 at 512 ms).
  void run(const std::function<void()>& work, bool heavy = false);

  int niceness() const { return niceness_; }
  int heavyNiceness() const { return heavyNiceness_; }  // in all, below the creator
  size_t threads() const { return threads_.size(); }    // the heavy lane's included
  size_t heavyQueued() const;  // heavy jobs waiting for the lane (the one running not counted)

 private:
  struct Job {
    const std::function<void()>* work;
    std::exception_ptr error;
    bool done = false;
  };
  struct Lane {
    std::deque<Job*> jobs;
    std::condition_variable queued;  // a job arrived, or stopping
  };
  void serve(Lane& lane, int niceness, bool loopsHere);

  const int niceness_, heavyNiceness_;
  mutable std::mutex mutex_;
  std::condition_variable done_;  // a job finished
  Lane light_, heavy_;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace penumbra::server
