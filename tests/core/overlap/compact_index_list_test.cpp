// CompactIndexList against a plain vector model: seeded random pushes and removals, copies
// and moves, and the block freed when empty.
#include "core/overlap/compact_index_list.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace penumbra {
namespace {

std::vector<uint32_t> sorted(const CompactIndexList& list) {
  std::vector<uint32_t> out(list.begin(), list.end());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(CompactIndexList, RandomPushesAndRemovalsMatchAMultisetModel) {
  std::mt19937_64 rng(20261128);
  std::vector<CompactIndexList> lists(16);
  std::vector<std::vector<uint32_t>> model(16);
  for (int step = 0; step < 50000; ++step) {
    const size_t k = rng() % lists.size();
    const uint32_t value = uint32_t(rng() % 40);
    if (rng() % 3 != 0) {
      lists[k].push_back(value);
      model[k].push_back(value);
    } else {
      const auto at = std::find(model[k].begin(), model[k].end(), value);
      const bool present = at != model[k].end();
      if (present) model[k].erase(at);
      ASSERT_EQ(lists[k].removeOne(value), present) << "step " << step;
    }
    ASSERT_EQ(lists[k].size(), model[k].size());
    ASSERT_EQ(lists[k].empty(), model[k].empty());
    std::vector<uint32_t> expected = model[k];
    std::sort(expected.begin(), expected.end());
    ASSERT_EQ(sorted(lists[k]), expected) << "step " << step;
  }
}

TEST(CompactIndexList, CopiesAreDeepAndMovesLeaveEmpty) {
  CompactIndexList a;
  EXPECT_TRUE(a.empty());
  EXPECT_EQ(a.begin(), a.end());
  EXPECT_FALSE(a.removeOne(3));
  for (uint32_t v : {5u, 7u, 5u}) a.push_back(v);
  CompactIndexList b = a;
  b.push_back(9);
  EXPECT_EQ(sorted(a), (std::vector<uint32_t>{5, 5, 7}));
  EXPECT_EQ(sorted(b), (std::vector<uint32_t>{5, 5, 7, 9}));
  b = a;
  EXPECT_EQ(sorted(b), sorted(a));
  const CompactIndexList& self = b;
  b = self;
  EXPECT_EQ(sorted(b), (std::vector<uint32_t>{5, 5, 7}));
  CompactIndexList c = std::move(b);
  EXPECT_TRUE(b.empty());  // NOLINT(bugprone-use-after-move): a moved-from list is empty
  EXPECT_EQ(sorted(c), (std::vector<uint32_t>{5, 5, 7}));
  for (uint32_t v : {5u, 7u, 5u}) EXPECT_TRUE(c.removeOne(v));
  EXPECT_TRUE(c.empty());
  EXPECT_EQ(c.begin(), c.end());
}

}  // namespace
}  // namespace penumbra
