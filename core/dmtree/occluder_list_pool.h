// The occluder lists of one half-edge mesh, each distinct list stored once and counted
// by the cells holding it. Neighbouring cells mostly hold the same list (a cut copies
// it to both halves): a sparse room of 541k cells has 77k distinct lists. Plain value,
// owned by its mesh; not thread-safe for writes.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/dmtree/occluder_list.h"

namespace penumbra {

class OccluderListPool {
 public:
  // A counted reference to one list. kEmpty, the empty list, is never counted or freed.
  using Handle = uint32_t;
  static constexpr Handle kEmpty = 0;

  OccluderListPool();

  // The list behind h. The reference stays valid until the next intern() or release():
  // read a list before changing any cell's (a deque would keep them in place, but costs
  // ~600 bytes a mesh, 2.7 MB over a sparse 1500 build's trees).
  const OccluderList& list(Handle h) const { return slots_[h].list; }
  // A counted reference to the slot holding a list equal to `list`, new if none is.
  Handle intern(const OccluderList& list);
  void retain(Handle h) {
    if (h != kEmpty) ++slots_[h].holders;
  }
  void release(Handle h);
  void clear();
  // Gives back the spare capacity of the stored lists.
  void shrinkToFit();

  size_t distinctLists() const { return byHash_.size(); }
  size_t holders(Handle h) const { return slots_[h].holders; }
  // Throws std::logic_error unless `holders[h]` (counted by the caller from its cells)
  // matches every slot's count and each live list is interned once.
  void validate(const std::vector<size_t>& holders) const;

 private:
  static uint64_t hashOf(const OccluderList& list);
  struct Slot {
    OccluderList list;
    uint64_t hash = 0;
    uint32_t holders = 0;  // 0: free (its index is in free_), except kEmpty's
  };
  std::vector<Slot> slots_;
  std::vector<Handle> free_;
  std::unordered_multimap<uint64_t, Handle> byHash_;  // live slots but kEmpty, by hashOf(list)
};

}  // namespace penumbra
