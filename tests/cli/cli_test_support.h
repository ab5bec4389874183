// Shared by the CLI tests: the program under test, runs of it, and a path for a test's scratch
// file that no other test uses (CTest runs tests of one binary in parallel), named after the
// running test.
#pragma once

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>

namespace penumbra::cli_test {

inline const std::string kBinary = std::string(PENUMBRA_BINARY_DIR) + "/penumbra";
inline const std::string kCornell = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell.scene.json";

inline std::string tempPath(const std::string& name) {
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string owner = test ? std::string(test->test_suite_name()) + "." + test->name() : "global";
  return std::string(PENUMBRA_BINARY_DIR) + "/cli_test_" + owner + "_" + name;
}

// `penumbra ARGUMENTS`' exit status (-1 when it did not exit), its output discarded.
inline int runQuiet(const std::string& arguments) {
  const int status = std::system((kBinary + " " + arguments + " 2>/dev/null >/dev/null").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// `penumbra ARGUMENTS`' exit status and what it wrote to stdout and stderr.
inline std::pair<int, std::string> runCaptured(const std::string& arguments) {
  const std::string out = tempPath("output.txt");
  const int status = std::system((kBinary + " " + arguments + " >" + out + " 2>&1").c_str());
  std::ifstream in(out);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  std::filesystem::remove(out);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text};
}

}  // namespace penumbra::cli_test
