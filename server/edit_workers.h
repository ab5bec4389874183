// The threads that apply edit batches (docs/API.md "Load"): one per core for light work, and one
// heavy lane below them for frames whose work grows with the whole scene. Reads take no lock
// (they serve immutable snapshots), but they share the cores with edits: with a batch applying
// on each scene's request thread, ten scenes edited at once meant ten relighting threads on two
// cores, and a 1 ms read waited behind them. Optionally (`serve --edit-nice K`) the workers
// also run K nice steps below the request threads, so that reads go first. Thread-safe.
#pragma once

#include <cstddef>
#include <functional>
#include <thread>

#include "server/work_lane.h"

namespace penumbra::server {

class EditWorkers {
 public:
  // `threads` light workers (0 or less: one per core), each `niceness` steps (0–19) below the
  // priority of the thread that makes them, and one heavy-lane thread `heavyNiceness` steps
  // further below (at most 19 in all). Destruction lets the queued work finish, then joins.
  EditWorkers(int threads, int niceness, int heavyNiceness);

  // Runs `work` on a worker (in arrival order when all are busy) and returns once it ran;
  // rethrows what it threw. Heavy work (a frame relighting the whole scene: isHeavyFrame) runs
  // on the heavy lane only: one job at a time, below the light workers' priority, its engine loops
  // on that one thread, so one user's heavy frames take at most one core and what is left of it,
  // and light work never queues behind them (two frames adding 22 lights each had held both
  // workers and another scene's 15 ms edit waited 44 s; a 20-light frame beside image renders
  // had put another client's drag p99 at 512 ms).
  void run(const std::function<void()>& work, bool heavy = false);

  int niceness() const { return light_.niceness(); }
  int heavyNiceness() const { return heavy_.niceness(); }  // in all, below the creator
  size_t threads() const { return light_.threads() + heavy_.threads(); }
  size_t heavyQueued() const { return heavy_.queued(); }  // the one running not counted

 private:
  WorkLane light_, heavy_;
};

}  // namespace penumbra::server
