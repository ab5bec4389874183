#include "server/work_budget.h"

namespace penumbra::server {

WorkBudget::Share::~Share() {
  if (budget_) budget_->give(bytes_);
}

std::optional<WorkBudget::Share> WorkBudget::tryTake(uint64_t bytes) {
  std::lock_guard lock(mutex_);
  if (bytes > capacity_ - used_) return std::nullopt;
  used_ += bytes;
  return Share(this, bytes);
}

uint64_t WorkBudget::inUse() const {
  std::lock_guard lock(mutex_);
  return used_;
}

void WorkBudget::give(uint64_t bytes) {
  std::lock_guard lock(mutex_);
  used_ -= bytes;
}

}  // namespace penumbra::server
