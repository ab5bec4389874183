// The random numbers of the stochastic BSDF estimators: a seeded 64-bit Mersenne twister giving
// uniform doubles in [0, 1). One per thread; not thread-safe.
#pragma once

#include <cstdint>
#include <random>

namespace penumbra::bsdf {

class Rng {
 public:
  explicit Rng(uint64_t seed) : gen_(seed) {}
  double uniform() { return double(gen_() >> 11) * 0x1.0p-53; }  // 53 random bits

 private:
  std::mt19937_64 gen_;
};

}  // namespace penumbra::bsdf
