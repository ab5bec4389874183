// BucketTable against std::map: seeded random inserts and look-ups over clustered and far
// keys (growth included); a value stays where it was put.
#include "core/mesh/bucket_table.h"

#include <gtest/gtest.h>

#include <map>
#include <random>

namespace penumbra {
namespace {

TEST(BucketTable, RandomInsertsAndFindsMatchAMap) {
  std::mt19937_64 rng(1128);
  for (int round = 0; round < 2; ++round) {
    BucketTable<uint64_t> table;
    std::map<std::pair<int64_t, int64_t>, uint64_t> model;
    for (int step = 0; step < 20000; ++step) {
      // Mostly a small neighbourhood (collisions, probing), sometimes anywhere in 64 bits.
      const bool far = rng() % 8 == 0;
      const int64_t x = far ? int64_t(rng()) : int64_t(rng() % 60) - 30;
      const int64_t y = far ? int64_t(rng()) : int64_t(rng() % 60) - 30;
      const uint64_t value = rng();
      if (rng() % 2) {
        const auto [stored, added] = table.tryEmplace(x, y, value);
        const auto [it, modelAdded] = model.try_emplace({x, y}, value);
        ASSERT_EQ(added, modelAdded) << "step " << step;
        ASSERT_EQ(*stored, it->second) << "step " << step;
      } else {
        const uint64_t* found = table.find(x, y);
        const auto it = model.find({x, y});
        ASSERT_EQ(found != nullptr, it != model.end()) << "step " << step;
        if (found) ASSERT_EQ(*found, it->second);
      }
      ASSERT_EQ(table.size(), model.size());
    }
    for (const auto& [key, value] : model) {
      const uint64_t* found = table.find(key.first, key.second);
      ASSERT_NE(found, nullptr);
      EXPECT_EQ(*found, value);
    }
  }
}

}  // namespace
}  // namespace penumbra
