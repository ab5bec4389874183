#include "server/elastic_pool.h"

#include <algorithm>
#include <chrono>

namespace penumbra::server {

ElasticPool::ElasticPool(size_t minThreads, size_t maxThreads, int idleSeconds)
    : minThreads_(std::max<size_t>(1, minThreads)),
      maxThreads_(std::max(maxThreads, std::max<size_t>(1, minThreads))),
      idleSeconds_(idleSeconds) {
  std::lock_guard lock(mutex_);
  for (size_t i = 0; i < minThreads_; ++i) startThread();
}

ElasticPool::~ElasticPool() { shutdown(); }

void ElasticPool::startThread() {
  // Threads that ended by themselves are joined here, so their handles do not pile up.
  for (const std::thread::id id : finished_) {
    const auto it = std::find_if(threads_.begin(), threads_.end(),
                                 [id](const std::thread& t) { return t.get_id() == id; });
    if (it != threads_.end()) {
      it->join();
      threads_.erase(it);
    }
  }
  finished_.clear();
  ++alive_;
  threads_.emplace_back([this] { work(); });
}

void ElasticPool::enqueue(std::function<void()> task) {
  std::lock_guard lock(mutex_);
  if (stopping_) return;
  tasks_.push_back(std::move(task));
  if (idle_ < tasks_.size() && alive_ < maxThreads_) startThread();
  ready_.notify_one();
}

void ElasticPool::work() {
  std::unique_lock lock(mutex_);
  for (;;) {
    ++idle_;
    const bool woken = ready_.wait_for(lock, std::chrono::seconds(idleSeconds_),
                                       [this] { return stopping_ || !tasks_.empty(); });
    --idle_;
    if (tasks_.empty() && (stopping_ || (!woken && alive_ > minThreads_))) break;
    if (tasks_.empty()) continue;
    std::function<void()> task = std::move(tasks_.front());
    tasks_.pop_front();
    lock.unlock();
    task();
    task = nullptr;  // the connection's state goes with it, outside the lock
    lock.lock();
  }
  --alive_;
  if (!stopping_) finished_.push_back(std::this_thread::get_id());
}

void ElasticPool::shutdown() {
  std::vector<std::thread> threads;
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && threads_.empty()) return;
    stopping_ = true;
    threads.swap(threads_);
  }
  ready_.notify_all();
  for (std::thread& thread : threads)
    if (thread.joinable()) thread.join();
}

size_t ElasticPool::threads() const {
  std::lock_guard lock(mutex_);
  return alive_;
}

}  // namespace penumbra::server
