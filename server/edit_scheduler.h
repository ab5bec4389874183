// Admission, order and grouping of one scene's edit frames: a bounded wait queue, one batch
// applying at a time, clients taking turns (round-robin), and the frames that queued while a
// batch applied taken together as the next batch — at most one per client (group commit,
// docs/API.md "Load"). Thread-safe; one per SceneSession.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace penumbra::server {

class EditScheduler {
 public:
  // One frame waiting; callers derive their request's data from it (edit_routes.cpp).
  struct Ticket {
    std::string client;
    bool done = false;  // set under the scheduler's lock once its batch was applied
  };
  // Applies a batch (frames in turn order) and leaves each ticket's answer in it. Must not
  // throw: a failure is each ticket's answer.
  using ApplyBatch = std::function<void(const std::vector<Ticket*>& batch)>;

  // At most `maxQueued` frames wait (the batch applying not counted); a batch holds at most
  // `maxBatch` frames.
  EditScheduler(size_t maxQueued, size_t maxBatch) : maxQueued_(maxQueued), maxBatch_(maxBatch) {}

  // Queues `ticket` and returns once a batch holding it was applied, by this thread or another:
  // when no batch is applying, the calling thread applies the next one (`apply`) — the oldest
  // waiting frame of each client in turn order — and goes on until its own frame is done.
  // Throws EditQueueFull (nothing queued) when maxQueued frames wait.
  void submit(Ticket& ticket, const ApplyBatch& apply);

  size_t queued() const;  // frames waiting now

 private:
  std::vector<Ticket*> takeBatch();  // with mutex_ held

  const size_t maxQueued_, maxBatch_;
  mutable std::mutex mutex_;
  std::condition_variable applied_;
  std::map<std::string, std::deque<Ticket*>> waiting_;  // per client, in arrival order
  std::deque<std::string> rotation_;  // clients with a frame waiting, in turn order
  size_t queued_ = 0;
  bool applying_ = false;
};

// Thrown by EditScheduler::submit when the queue is full (the server answers 503 busy).
struct EditQueueFull : std::exception {
  const char* what() const noexcept override { return "edit queue full"; }
};

}  // namespace penumbra::server
