#include "core/dmtree/occluder_list_pool.h"

#include <stdexcept>
#include <string>


namespace penumbra {

OccluderListPool::OccluderListPool() { slots_.emplace_back(); }

uint64_t OccluderListPool::hashOf(const OccluderList& list) {
  Fingerprint f;
  for (const OccluderEntry& e : list) addEntry(f, e);
  return f.value();
}

OccluderListPool::Handle OccluderListPool::intern(const OccluderList& list) {
  if (list.empty()) return kEmpty;
  const uint64_t hash = hashOf(list);
  const auto [first, last] = byHash_.equal_range(hash);
  for (auto it = first; it != last; ++it)
    if (slots_[it->second].list == list) {
      ++slots_[it->second].holders;
      return it->second;
    }
  OccluderList stored(list.begin(), list.end());  // exact size; copied first: `list` may be a slot's
  Handle h;
  if (free_.empty()) {
    h = static_cast<Handle>(slots_.size());
    slots_.emplace_back();
  } else {
    h = free_.back();
    free_.pop_back();
  }
  Slot& slot = slots_[h];
  slot.list = std::move(stored);
  slot.hash = hash;
  slot.holders = 1;
  byHash_.emplace(hash, h);
  return h;
}

void OccluderListPool::release(Handle h) {
  if (h == kEmpty) return;
  Slot& slot = slots_[h];
  if (slot.holders == 0) throw std::logic_error("OccluderListPool: released a free list");
  if (--slot.holders) return;
  const auto [first, last] = byHash_.equal_range(slot.hash);
  for (auto it = first; it != last; ++it)
    if (it->second == h) {
      byHash_.erase(it);
      break;
    }
  OccluderList().swap(slot.list);
  free_.push_back(h);
}

void OccluderListPool::clear() {
  slots_.clear();
  slots_.emplace_back();
  free_.clear();
  byHash_.clear();
}

void OccluderListPool::shrinkToFit() {
  slots_.shrink_to_fit();
  free_.shrink_to_fit();
}

void OccluderListPool::validate(const std::vector<size_t>& holders) const {
  auto fail = [](const std::string& what) { throw std::logic_error("OccluderListPool: " + what); };
  if (holders.size() > slots_.size()) fail("a cell holds a list past the pool");
  size_t live = 0;
  for (Handle h = 1; h < slots_.size(); ++h) {
    const Slot& slot = slots_[h];
    if (slot.holders != (h < holders.size() ? holders[h] : 0))
      fail("list " + std::to_string(h) + " counts " + std::to_string(slot.holders) + " holders");
    if (!slot.holders) continue;
    ++live;
    if (slot.list.empty() || slot.hash != hashOf(slot.list)) fail("list " + std::to_string(h) + " hashed wrong");
    const auto [first, last] = byHash_.equal_range(slot.hash);
    size_t same = 0, self = 0;
    for (auto it = first; it != last; ++it) {
      same += slots_[it->second].list == slot.list;
      self += it->second == h;
    }
    if (same != 1 || self != 1) fail("list " + std::to_string(h) + " interned " + std::to_string(same) + " times");
  }
  if (live != byHash_.size()) fail("the index holds free lists");
}

}  // namespace penumbra
