// Fingerprint: any one changed bit, moved word or changed length of the data gives another
// value (seeded; runs of 32 bytes take the four-lane path, tails the serial one).
#include "core/geom/fingerprint.h"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

namespace penumbra {
namespace {

uint64_t of(const std::vector<uint64_t>& words, size_t bytes) {
  Fingerprint f;
  f.addBytes(std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(words.data()), bytes));
  return f.value();
}

TEST(Fingerprint, EveryBitFlipSwapAndLengthChangesTheValue) {
  std::mt19937_64 rng(1128);
  for (size_t bytes : {1u, 7u, 8u, 31u, 32u, 33u, 64u, 100u, 256u}) {
    std::vector<uint64_t> words((bytes + 7) / 8 + 1);
    for (uint64_t& w : words) w = rng();
    const uint64_t base = of(words, bytes);
    std::set<uint64_t> seen{base};
    for (size_t bit = 0; bit < 8 * bytes; ++bit) {
      std::vector<uint64_t> flipped = words;
      flipped[bit / 64] ^= uint64_t(1) << (bit % 64);
      EXPECT_TRUE(seen.insert(of(flipped, bytes)).second) << bytes << " bytes, bit " << bit;
    }
    if (bytes >= 16 && words[0] != words[1]) {
      std::vector<uint64_t> swapped = words;
      std::swap(swapped[0], swapped[1]);
      EXPECT_NE(of(swapped, bytes), base) << bytes << " bytes";
    }
    std::vector<uint64_t> zeros((bytes + 7) / 8 + 2, 0);
    EXPECT_NE(of(zeros, bytes), of(zeros, bytes + 1)) << "length " << bytes;
    EXPECT_EQ(of(words, bytes), base);  // a pure function of the bytes
  }
}

}  // namespace
}  // namespace penumbra
