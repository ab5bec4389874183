// parseJsonText: the size and depth limits and syntax errors of untrusted text.
#include <string>

#include <gtest/gtest.h>

#include "protocol/json_text.h"
#include "protocol/validation_error.h"

namespace penumbra::protocol {
namespace {

// The ValidationError thrown by parsing text (fails the test if none is).
ValidationError refusal(const std::string& text, size_t maxBytes = kMaxJsonFileBytes, int maxDepth = kMaxJsonDepth) {
  try {
    (void)parseJsonText(text, maxBytes, maxDepth);
  } catch (const ValidationError& e) {
    EXPECT_EQ(e.path(), kJsonTextPath);
    return e;
  }
  ADD_FAILURE() << "accepted: " << text;
  return ValidationError("", "");
}

std::string nested(int depth) { return std::string(size_t(depth), '[') + std::string(size_t(depth), ']'); }

TEST(JsonText, AcceptsValidText) {
  const auto j = parseJsonText(R"({"a": [1, 2.5, "x"], "b": {"c": null}})", 100, 3);
  EXPECT_EQ(j["a"][1], 2.5);
  EXPECT_TRUE(j["b"]["c"].is_null());
}

TEST(JsonText, RefusesOversizeInput) {
  const std::string text = R"({"key": "value"})";  // 16 bytes
  EXPECT_NO_THROW((void)parseJsonText(text, text.size(), kMaxJsonDepth));
  const ValidationError e = refusal(text, text.size() - 1);
  EXPECT_NE(e.problem().find(std::to_string(text.size()) + " bytes, over the limit of " +
                             std::to_string(text.size() - 1)),
            std::string::npos)
      << e.what();
}

TEST(JsonText, RefusesOverDepthInput) {
  EXPECT_NO_THROW((void)parseJsonText(nested(10), 1000, 10));
  const ValidationError e = refusal(nested(11), 1000, 10);
  EXPECT_NE(e.problem().find("deeper than the limit of 10"), std::string::npos) << e.what();
  // Objects count as levels too.
  EXPECT_NE(refusal(R"({"a": {"b": {"c": 1}}})", 1000, 2).problem().find("deeper"), std::string::npos);
  // A very deep document is refused cheaply rather than overflowing anything.
  EXPECT_NE(refusal(nested(1'000'000), 10'000'000).problem().find("deeper"), std::string::npos);
}

TEST(JsonText, BracketsInsideStringsDoNotCount) {
  EXPECT_NO_THROW((void)parseJsonText(R"(["[[[[{{{{", "\"[[[["])", 1000, 1));
}

TEST(JsonText, RefusesMalformedTextWithBytePosition) {
  // nlohmann counts bytes read, so the offending character's 1-based position.
  const std::string text = "[1, 2, x]";
  const ValidationError e = refusal(text);
  const size_t bad = text.find('x') + 1;
  EXPECT_NE(e.problem().find("invalid JSON at byte " + std::to_string(bad)), std::string::npos) << e.what();
  EXPECT_EQ(e.problem().find("[json.exception"), std::string::npos) << "library prefix leaked: " << e.what();

  EXPECT_NE(refusal("").problem().find("invalid JSON"), std::string::npos);
  EXPECT_NE(refusal(R"({"a": [1, 2,]})").problem().find("invalid JSON"), std::string::npos);
  EXPECT_NE(refusal("{} trailing").problem().find("invalid JSON"), std::string::npos);
  EXPECT_NE(refusal("[NaN]").problem().find("invalid JSON"), std::string::npos);
  EXPECT_NE(refusal("[\"\xff\"]").problem().find("invalid JSON"), std::string::npos);
}

TEST(JsonText, RefusesNumbersBeyondDouble) {
  const ValidationError e = refusal("[1e400]");
  EXPECT_NE(e.problem().find("overflow"), std::string::npos) << e.what();
  EXPECT_NE(refusal("[-1e400]").problem().find("overflow"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::protocol
