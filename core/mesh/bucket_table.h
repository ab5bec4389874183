// The receiver mesh builder's buckets: integer grid cells (x, y) to the chain of locations in
// each, in one open-addressing array (linear probing, grown at half load). A node-based
// std::unordered_map cost a heap block per bucket and most of the builder's time. Only find
// and insert: nothing is erased but all at once (clear). Not thread-safe to write.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace penumbra {

template <class Value>
class BucketTable {
 public:
  // The value at (x, y), or null.
  Value* find(int64_t x, int64_t y) {
    if (slots_.empty()) return nullptr;
    for (size_t i = indexOf(x, y);; i = (i + 1) & mask_) {
      Slot& s = slots_[i];
      if (!s.used) return nullptr;
      if (s.x == x && s.y == y) return &s.value;
    }
  }
  // The value at (x, y) and true if it was added (as `value`), false if already there.
  std::pair<Value*, bool> tryEmplace(int64_t x, int64_t y, const Value& value) {
    if (2 * (size_ + 1) > slots_.size()) grow();
    for (size_t i = indexOf(x, y);; i = (i + 1) & mask_) {
      Slot& s = slots_[i];
      if (!s.used) {
        s = Slot{x, y, value, true};
        ++size_;
        return {&s.value, true};
      }
      if (s.x == x && s.y == y) return {&s.value, false};
    }
  }
  size_t size() const { return size_; }
  // Empties the table, keeping its slots.
  void clear() {
    for (Slot& s : slots_) s.used = false;
    size_ = 0;
  }

 private:
  struct Slot {
    int64_t x = 0, y = 0;
    Value value{};
    bool used = false;
  };
  size_t indexOf(int64_t x, int64_t y) const {
    // splitmix64's finaliser over both coordinates: neighbouring cells spread apart.
    uint64_t h = uint64_t(x) * 0x9e3779b97f4a7c15ull ^ (uint64_t(y) + 0x632be59bd9b4e019ull);
    h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
    h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
    return size_t(h ^ (h >> 31)) & mask_;
  }
  void grow() {
    std::vector<Slot> old = std::move(slots_);
    slots_.assign(old.empty() ? 64 : 2 * old.size(), Slot{});
    mask_ = slots_.size() - 1;
    size_ = 0;
    for (const Slot& s : old)
      if (s.used) tryEmplace(s.x, s.y, s.value);
  }
  std::vector<Slot> slots_;  // a power of two long
  size_t mask_ = 0;
  size_t size_ = 0;
};

}  // namespace penumbra
