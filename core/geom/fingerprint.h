// A 64-bit fingerprint of plain data (doubles by bit pattern, integers), chained
// word by word through the splitmix64 finaliser. For change detection where keeping
// the data itself costs too much memory; not for adversarial keys. Plain value.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>

namespace penumbra {

class Fingerprint {
 public:
  void add(uint64_t word) { hash_ = mix(hash_ ^ word); }
  void add(double value) {
    uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    add(bits);
  }
  // Trivially copyable values without padding, word by word (the tail zero-padded). Runs of
  // 32 bytes go through four independent chains folded in at the end: one chain waits on
  // each multiply, four keep the core busy (cell fingerprints hash kilobytes of points).
  template <class T>
  void addBytes(std::span<const T> values) {
    static_assert(std::is_trivially_copyable_v<T>);
    add(uint64_t(values.size()));
    const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
    const size_t size = values.size_bytes();
    size_t i = 0;
    if (size >= 32) {
      uint64_t lanes[4] = {hash_, hash_ ^ 0x13198a2e03707344ull, hash_ ^ 0xa4093822299f31d0ull,
                           hash_ ^ 0x082efa98ec4e6c89ull};
      for (; i + 32 <= size; i += 32)
        for (int k = 0; k < 4; ++k) lanes[k] = mix(lanes[k] ^ load(bytes + i + 8 * k));
      for (uint64_t lane : lanes) add(lane);
    }
    for (; i < size; i += 8) {
      uint64_t word = 0;
      std::memcpy(&word, bytes + i, size - i < 8 ? size - i : 8);
      add(word);
    }
  }
  uint64_t value() const { return hash_; }

 private:
  // The splitmix64 step: add the golden gamma, then its finaliser.
  static uint64_t mix(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
  }
  static uint64_t load(const unsigned char* at) {
    uint64_t word;
    std::memcpy(&word, at, sizeof word);
    return word;
  }
  uint64_t hash_ = 0x243f6a8885a308d3ull;
};

}  // namespace penumbra
