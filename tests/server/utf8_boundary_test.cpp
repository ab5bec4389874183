// isValidUtf8 agrees with nlohmann's JSON lexer (which refuses ill-formed UTF-8 in strings)
// on seeded random byte strings biased to the tricky leads (overlongs, surrogates, > U+10FFFF).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <random>
#include <string>

#include "server/utf8_boundary.h"

namespace penumbra::server {
namespace {

TEST(Utf8Boundary, AgreesWithNlohmannsLexerSeeded) {
  const unsigned char bytes[] = {'a',  'z',  0x7F, 0x80, 0x8F, 0x90, 0x9F, 0xA0, 0xBF, 0xC0, 0xC1,
                                 0xC2, 0xDF, 0xE0, 0xE1, 0xED, 0xEF, 0xF0, 0xF4, 0xF5, 0xF8, 0xFF};
  std::mt19937_64 rng(12);
  size_t valid = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::string text;
    for (size_t i = 0, n = 1 + rng() % 6; i < n; ++i) text += char(bytes[rng() % sizeof bytes]);
    const bool lexer = nlohmann::json::accept("\"" + text + "\"");
    EXPECT_EQ(isValidUtf8(text), lexer) << trial;
    valid += lexer;
  }
  EXPECT_GT(valid, 500u);  // both answers are well represented (660 with this seed)
  EXPECT_TRUE(isValidUtf8("\xF4\x8F\xBF\xBF"));
  EXPECT_FALSE(isValidUtf8("\xED\xA0\x80"));  // a surrogate
  EXPECT_FALSE(isValidUtf8("\xC0\xAF"));      // overlong '/'
}

}  // namespace
}  // namespace penumbra::server
