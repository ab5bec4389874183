// Shared by the CLI tests: a path for a test's scratch file that no other test uses
// (CTest runs tests of one binary in parallel), named after the running test.
#pragma once

#include <gtest/gtest.h>

#include <string>

namespace penumbra::cli_test {

inline std::string tempPath(const std::string& name) {
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string owner = test ? std::string(test->test_suite_name()) + "." + test->name() : "global";
  return std::string(PENUMBRA_BINARY_DIR) + "/cli_test_" + owner + "_" + name;
}

}  // namespace penumbra::cli_test
