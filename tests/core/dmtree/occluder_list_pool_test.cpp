// The interned occluder lists: equal lists share one counted slot, the last release
// frees it for reuse, and validate() catches counts that disagree with the holders.
// A seeded random sequence of interns and releases is checked against a plain model.
#include "core/dmtree/occluder_list_pool.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

namespace penumbra {
namespace {

OccluderList listOf(std::initializer_list<uint32_t> objects, bool umbraFirst = false) {
  OccluderList list;
  for (uint32_t o : objects) list.push_back(OccluderEntry(0, FaceId{o, 0}, umbraFirst && list.empty()));
  return list;
}

TEST(OccluderListPool, EqualListsShareOneSlot) {
  OccluderListPool pool;
  EXPECT_EQ(pool.intern({}), OccluderListPool::kEmpty);
  const auto a = pool.intern(listOf({1, 2}));
  const auto b = pool.intern(listOf({1, 2}));
  const auto c = pool.intern(listOf({2, 1}));        // order matters
  const auto d = pool.intern(listOf({1, 2}, true));  // so does the umbra flag
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  EXPECT_NE(a, d);
  EXPECT_NE(c, d);
  EXPECT_EQ(pool.holders(a), 2u);
  EXPECT_EQ(pool.distinctLists(), 3u);
  EXPECT_EQ(pool.list(a), listOf({1, 2}));
  EXPECT_NO_THROW(pool.validate({0, 2, 1, 1}));
}

TEST(OccluderListPool, TheLastReleaseFreesTheSlotForReuse) {
  OccluderListPool pool;
  const auto a = pool.intern(listOf({7}));
  pool.retain(a);
  pool.release(a);
  EXPECT_EQ(pool.distinctLists(), 1u);
  pool.release(a);
  EXPECT_EQ(pool.distinctLists(), 0u);
  EXPECT_THROW(pool.release(a), std::logic_error);
  const auto b = pool.intern(listOf({8, 9}));
  EXPECT_EQ(b, a);  // the freed slot, holding the new list
  EXPECT_EQ(pool.list(b), listOf({8, 9}));
  pool.release(OccluderListPool::kEmpty);  // the empty list is never counted
  EXPECT_EQ(pool.list(OccluderListPool::kEmpty).size(), 0u);
}

TEST(OccluderListPool, ValidateCatchesWrongCounts) {
  OccluderListPool pool;
  const auto a = pool.intern(listOf({1}));
  std::vector<size_t> holders(a + 1, 0);
  holders[a] = 1;
  EXPECT_NO_THROW(pool.validate(holders));
  holders[a] = 2;
  EXPECT_THROW(pool.validate(holders), std::logic_error);
  holders.push_back(1);  // a holder of a free slot
  holders[a] = 1;
  EXPECT_THROW(pool.validate(holders), std::logic_error);
}

TEST(OccluderListPool, RandomInternsAndReleasesMatchAModelSeeded) {
  std::mt19937 rng(20261127);
  OccluderListPool pool;
  std::vector<std::pair<OccluderListPool::Handle, OccluderList>> held;
  for (int step = 0; step < 20000; ++step) {
    if (held.empty() || rng() % 3) {
      OccluderList list;
      const size_t n = rng() % 4;
      for (size_t i = 0; i < n; ++i) list.push_back(OccluderEntry(rng() % 2, FaceId{uint32_t(rng() % 3), 0}, i == 0 && rng() % 2));
      held.emplace_back(pool.intern(list), list);
    } else {
      const size_t k = rng() % held.size();
      pool.release(held[k].first);
      held.erase(held.begin() + long(k));
    }
    if (step % 997) continue;
    std::vector<size_t> holders;
    for (const auto& [h, list] : held) {
      ASSERT_EQ(pool.list(h), list);
      for (const auto& [other, otherList] : held) ASSERT_EQ(other == h, otherList == list) << "two slots for one list";
      if (h == OccluderListPool::kEmpty) continue;
      if (h >= holders.size()) holders.resize(h + 1);
      ++holders[h];
    }
    ASSERT_NO_THROW(pool.validate(holders));
  }
}

}  // namespace
}  // namespace penumbra
