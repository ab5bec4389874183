#include "server/edit_scheduler.h"

namespace penumbra::server {

EditScheduler::Turn EditScheduler::wait(const std::string& client) {
  std::unique_lock lock(mutex_);
  if (queued_ >= maxQueued_) throw EditQueueFull();
  const uint64_t ticket = nextTicket_++;
  std::deque<uint64_t>& mine = tickets_[client];
  if (mine.empty()) rotation_.push_back(client);
  mine.push_back(ticket);
  ++queued_;
  if (current_ == 0) grantNext();
  granted_.wait(lock, [&] { return current_ == ticket; });
  return Turn(this);
}

size_t EditScheduler::queued() const {
  std::lock_guard lock(mutex_);
  return queued_;
}

void EditScheduler::release() {
  std::lock_guard lock(mutex_);
  current_ = 0;
  grantNext();
}

void EditScheduler::grantNext() {
  if (rotation_.empty()) return;
  const std::string client = std::move(rotation_.front());
  rotation_.pop_front();
  const auto it = tickets_.find(client);
  current_ = it->second.front();
  it->second.pop_front();
  --queued_;
  // A client with more frames waiting goes to the back: one frame per client per round.
  if (it->second.empty())
    tickets_.erase(it);
  else
    rotation_.push_back(client);
  granted_.notify_all();
}

}  // namespace penumbra::server
