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
  void add(uint64_t word) {
    uint64_t x = hash_ ^ word;
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    hash_ = x ^ (x >> 31);
  }
  void add(double value) {
    uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    add(bits);
  }
  // Trivially copyable values without padding, word by word (the tail zero-padded).
  template <class T>
  void addBytes(std::span<const T> values) {
    static_assert(std::is_trivially_copyable_v<T>);
    add(uint64_t(values.size()));
    const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
    const size_t size = values.size_bytes();
    for (size_t i = 0; i < size; i += 8) {
      uint64_t word = 0;
      std::memcpy(&word, bytes + i, size - i < 8 ? size - i : 8);
      add(word);
    }
  }
  uint64_t value() const { return hash_; }

 private:
  uint64_t hash_ = 0x243f6a8885a308d3ull;
};

}  // namespace penumbra
