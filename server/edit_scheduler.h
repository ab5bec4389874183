// Admission and order of one scene's edit frames: a bounded wait queue, one frame at a time,
// round-robin between clients (docs/API.md "Load"). Thread-safe; one per SceneSession's user.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>

namespace penumbra::server {

class EditScheduler {
 public:
  // At most `maxQueued` frames wait (the one applying not counted).
  explicit EditScheduler(size_t maxQueued) : maxQueued_(maxQueued) {}

  // Held while one frame applies; the next client's frame is granted on destruction.
  class Turn {
   public:
    explicit Turn(EditScheduler* owner) : owner_(owner) {}
    Turn(Turn&& other) noexcept : owner_(other.owner_) { other.owner_ = nullptr; }
    Turn(const Turn&) = delete;
    Turn& operator=(const Turn&) = delete;
    Turn& operator=(Turn&&) = delete;
    ~Turn() {
      if (owner_) owner_->release();
    }

   private:
    EditScheduler* owner_;
  };

  // Waits for `client`'s turn. Clients take turns: after a client's frame, every other
  // client with a frame waiting goes first. Throws EditQueueFull when maxQueued wait.
  Turn wait(const std::string& client);

  size_t queued() const;  // frames waiting now

 private:
  void release();
  void grantNext();  // with mutex_ held

  const size_t maxQueued_;
  mutable std::mutex mutex_;
  std::condition_variable granted_;
  std::map<std::string, std::deque<uint64_t>> tickets_;  // per client, in arrival order
  std::deque<std::string> rotation_;  // clients with a ticket waiting, in turn order
  size_t queued_ = 0;
  uint64_t nextTicket_ = 1;
  uint64_t current_ = 0;  // the ticket applying now; 0: none
};

// Thrown by EditScheduler::wait when the queue is full (the server answers 503 busy).
struct EditQueueFull : std::exception {
  const char* what() const noexcept override { return "edit queue full"; }
};

}  // namespace penumbra::server
