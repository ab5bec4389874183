// httplib's task queue with a thread per connection when needed: cpp-httplib serves a
// connection on one worker until it closes, so a fixed pool of N workers is blocked by N slow
// clients (130 sockets sending a byte every 3 s held all 128 and /api/health never answered).
// This pool keeps `minThreads` and starts another thread whenever a connection arrives with none
// idle, up to `maxThreads` (then connections wait their turn); threads above the minimum end
// after `idleSeconds` without work. A blocked thread costs a stack reservation, not memory.
#pragma once

#include <httplib.h>

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace penumbra::server {

class ElasticPool : public httplib::TaskQueue {
 public:
  ElasticPool(size_t minThreads, size_t maxThreads, int idleSeconds);
  ~ElasticPool() override;

  void enqueue(std::function<void()> task) override;
  void shutdown() override;  // runs what is queued, then joins every thread

  size_t threads() const;  // alive now

 private:
  void startThread();  // with mutex_ held
  void work();

  const size_t minThreads_, maxThreads_;
  const int idleSeconds_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::function<void()>> tasks_;
  std::vector<std::thread> threads_;       // every thread started (joined at shutdown)
  std::vector<std::thread::id> finished_;  // ended by themselves, to be joined
  size_t alive_ = 0, idle_ = 0;
  bool stopping_ = false;
};

}  // namespace penumbra::server
