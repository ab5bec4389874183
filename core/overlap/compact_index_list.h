// A growable list of 32-bit indices in one heap block: 8 bytes when empty, its size and
// capacity kept in the block's first two words. The overlap cube keeps one per tile (6·G²:
// 216,600 at 9,006 faces, many empty), where a std::vector would cost 24 bytes each.
// Plain value; not thread-safe to write.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>

namespace penumbra {

class CompactIndexList {
 public:
  CompactIndexList() = default;
  CompactIndexList(const CompactIndexList& other) { *this = other; }
  CompactIndexList& operator=(const CompactIndexList& other) {
    if (this == &other) return *this;
    block_.reset();
    if (!other.empty()) {
      block_ = std::make_unique_for_overwrite<uint32_t[]>(kHeader + other.size());
      block_[0] = block_[1] = uint32_t(other.size());
      std::copy(other.begin(), other.end(), block_.get() + kHeader);
    }
    return *this;
  }
  CompactIndexList(CompactIndexList&&) noexcept = default;
  CompactIndexList& operator=(CompactIndexList&&) noexcept = default;

  size_t size() const { return block_ ? block_[0] : 0; }
  bool empty() const { return size() == 0; }
  const uint32_t* begin() const { return block_ ? block_.get() + kHeader : nullptr; }
  const uint32_t* end() const { return begin() + size(); }

  void push_back(uint32_t value) {
    const uint32_t n = uint32_t(size());
    if (!block_ || n == block_[1]) grow(n == 0 ? 2 : 2 * n);
    block_[kHeader + n] = value;
    block_[0] = n + 1;
  }
  // Removes one entry equal to `value` (the last entry takes its place); false if none.
  // The block is freed when the list becomes empty.
  bool removeOne(uint32_t value) {
    uint32_t* first = block_ ? block_.get() + kHeader : nullptr;
    uint32_t* last = first + size();
    uint32_t* at = std::find(first, last, value);
    if (at == last) return false;
    *at = *(last - 1);
    if (--block_[0] == 0) block_.reset();
    return true;
  }

 private:
  static constexpr size_t kHeader = 2;  // size, capacity
  void grow(uint32_t capacity) {
    auto bigger = std::make_unique_for_overwrite<uint32_t[]>(kHeader + capacity);
    const uint32_t n = uint32_t(size());
    if (n) std::copy(begin(), end(), bigger.get() + kHeader);
    bigger[0] = n;
    bigger[1] = capacity;
    block_ = std::move(bigger);
  }
  std::unique_ptr<uint32_t[]> block_;  // [size, capacity, entries...]; null when empty
};
static_assert(sizeof(CompactIndexList) == 8);

}  // namespace penumbra
