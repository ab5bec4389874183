// A set of indices [0, size) emptied in O(1): an index is in the set while its stamp is the
// current round's. The passes over a large mesh that touch a few of its corners, faces or
// clusters per point keep one per thread (thread_local) and start a round per call, so no
// call pays for the whole mesh. Not thread-safe; a round is valid until the next clear().
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace penumbra {

class StampedSet {
 public:
  // Starts a new, empty round over indices [0, size) (grows, never shrinks).
  void clear(size_t size) {
    if (stamps_.size() < size) stamps_.resize(size, 0);
    if (++stamp_ == 0) std::fill(stamps_.begin(), stamps_.end(), 0), stamp_ = 1;  // wrapped
  }
  bool contains(size_t i) const { return stamps_[i] == stamp_; }
  void insert(size_t i) { stamps_[i] = stamp_; }
  void erase(size_t i) { stamps_[i] = 0; }  // 0 is never a round's stamp
  // Inserts i; whether it was not in the set before.
  bool tryInsert(size_t i) {
    if (stamps_[i] == stamp_) return false;
    stamps_[i] = stamp_;
    return true;
  }
  // The raw marks, for a view kept past this object's use (ClusterSet): i is in the set iff
  // stamps()[i] == stamp().
  std::span<const uint32_t> stamps(size_t size) const { return {stamps_.data(), size}; }
  uint32_t stamp() const { return stamp_; }

 private:
  std::vector<uint32_t> stamps_;
  uint32_t stamp_ = 0;
};

// Values memoised per index for one round: value(i, compute) computes i's once per round.
template <class T>
class StampedMemo {
 public:
  void clear(size_t size) {
    known_.clear(size);
    if (values_.size() < size) values_.resize(size);
  }
  template <class Compute>
  const T& value(size_t i, const Compute& compute) {
    if (known_.tryInsert(i)) values_[i] = compute(i);
    return values_[i];
  }

 private:
  StampedSet known_;
  std::vector<T> values_;
};

}  // namespace penumbra
