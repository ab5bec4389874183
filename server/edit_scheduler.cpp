#include "server/edit_scheduler.h"

namespace penumbra::server {

void EditScheduler::submit(Ticket& ticket, const ApplyBatch& apply) {
  std::unique_lock lock(mutex_);
  if (queued_ >= maxQueued_) throw EditQueueFull();
  ticket.done = false;
  std::deque<Ticket*>& mine = waiting_[ticket.client];
  if (mine.empty()) rotation_.push_back(ticket.client);
  mine.push_back(&ticket);
  ++queued_;
  while (!ticket.done) {
    if (applying_) {
      applied_.wait(lock);
      continue;
    }
    applying_ = true;
    const std::vector<Ticket*> batch = takeBatch();
    lock.unlock();
    try {
      apply(batch);  // answers are in the tickets
    } catch (...) {
      // Against the contract: the tickets keep the answer they were created with.
    }
    lock.lock();
    for (Ticket* t : batch) t->done = true;
    applying_ = false;
    applied_.notify_all();  // the batch's waiters return; one of the others applies next
  }
}

size_t EditScheduler::queued() const {
  std::lock_guard lock(mutex_);
  return queued_;
}

std::vector<EditScheduler::Ticket*> EditScheduler::takeBatch() {
  // One frame per client, in turn order; a client with more waiting goes to the back.
  std::vector<Ticket*> batch;
  for (size_t turns = rotation_.size(); turns > 0 && batch.size() < maxBatch_; --turns) {
    const std::string client = std::move(rotation_.front());
    rotation_.pop_front();
    const auto it = waiting_.find(client);
    batch.push_back(it->second.front());
    it->second.pop_front();
    --queued_;
    if (it->second.empty())
      waiting_.erase(it);
    else
      rotation_.push_back(client);
  }
  return batch;
}

}  // namespace penumbra::server
