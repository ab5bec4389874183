// StampedSet and StampedMemo (stamped_set.h) against a plain std::set and a count of calls, on
// seeded random rounds of inserts, erases and lookups whose index range grows and shrinks
// (a thread's set serves meshes of different sizes in turn).
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "core/util/stamped_set.h"

namespace penumbra {
namespace {

TEST(StampedSet, RoundsBehaveAsFreshSets) {
  std::mt19937_64 rng(41);
  StampedSet set;
  for (int round = 0; round < 300; ++round) {
    const size_t size = 1 + rng() % 200;
    set.clear(size);
    std::set<size_t> model;
    for (int op = 0; op < 400; ++op) {
      const size_t i = rng() % size;
      switch (rng() % 4) {
        case 0:
          set.insert(i), model.insert(i);
          break;
        case 1:
          set.erase(i), model.erase(i);
          break;
        case 2:
          ASSERT_EQ(set.tryInsert(i), model.insert(i).second) << "round " << round << " index " << i;
          break;
        default:
          break;
      }
      ASSERT_EQ(set.contains(i), model.count(i) == 1) << "round " << round << " index " << i;
    }
    for (size_t i = 0; i < size; ++i) {
      ASSERT_EQ(set.contains(i), model.count(i) == 1) << "round " << round << " index " << i;
      ASSERT_EQ(set.stamps(size)[i] == set.stamp(), model.count(i) == 1);
    }
  }
}

TEST(StampedMemo, ComputesEachIndexOncePerRound) {
  std::mt19937_64 rng(42);
  StampedMemo<double> memo;
  for (int round = 0; round < 100; ++round) {
    const size_t size = 1 + rng() % 100;
    memo.clear(size);
    std::vector<int> calls(size, 0);
    const double salt = double(round);
    for (int op = 0; op < 300; ++op) {
      const size_t i = rng() % size;
      const double value = memo.value(i, [&](size_t j) {
        ++calls[j];
        return salt * 1000 + double(j);
      });
      ASSERT_EQ(value, salt * 1000 + double(i)) << "round " << round;  // this round's value, not a stale one
      ASSERT_EQ(calls[i], 1) << "round " << round << " index " << i;
    }
  }
}

}  // namespace
}  // namespace penumbra
