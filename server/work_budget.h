// A budget of working memory shared by costly requests (images, GI): each takes its estimated
// bytes before it starts and gives them back when done. A request that could never fit is
// refused by its route (400 naming the limit); one that does not fit now gets 503 `busy` with
// Retry-After, so concurrent large requests cannot add up past the machine (four 4096² GI
// images peaked at 5.1 GB before). Thread-safe.
#pragma once

#include <cstdint>
#include <mutex>
#include <optional>

namespace penumbra::server {

class WorkBudget {
 public:
  explicit WorkBudget(uint64_t capacityBytes) : capacity_(capacityBytes) {}
  WorkBudget(const WorkBudget&) = delete;
  WorkBudget& operator=(const WorkBudget&) = delete;

  // Holds bytes of the budget until destroyed.
  class Share {
   public:
    Share(Share&& other) noexcept : budget_(other.budget_), bytes_(other.bytes_) {
      other.budget_ = nullptr;
    }
    Share(const Share&) = delete;
    Share& operator=(const Share&) = delete;
    Share& operator=(Share&&) = delete;
    ~Share();

   private:
    friend class WorkBudget;
    Share(WorkBudget* budget, uint64_t bytes) : budget_(budget), bytes_(bytes) {}
    WorkBudget* budget_;
    uint64_t bytes_;
  };

  // `bytes` of the budget if they are free now; nullopt when taken by others (or more than
  // the whole capacity: check fits() first to tell the two apart).
  std::optional<Share> tryTake(uint64_t bytes);
  bool fits(uint64_t bytes) const { return bytes <= capacity_; }
  uint64_t capacity() const { return capacity_; }
  uint64_t inUse() const;

 private:
  void give(uint64_t bytes);

  const uint64_t capacity_;
  mutable std::mutex mutex_;
  uint64_t used_ = 0;
};

}  // namespace penumbra::server
