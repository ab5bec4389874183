// Helpers shared by the interchange tests: a scratch directory per test, files
// written there, and the `penumbra` binary. Test-only; not thread-safe.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace penumbra::interchange::testing {

inline const std::string kData = std::string(PENUMBRA_SOURCE_DIR) + "/tests/interchange/data";
inline const std::string kBinary = std::string(PENUMBRA_BINARY_DIR) + "/penumbra";

// A fresh directory named after the running test.
inline std::filesystem::path scratchDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir = std::filesystem::path(PENUMBRA_BINARY_DIR) / "interchange_test" /
                                    (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string writeFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

// Runs `penumbra ARGUMENTS`, stdout and stderr into files beside `log`; the exit status.
inline int runPenumbra(const std::string& arguments, const std::filesystem::path& log) {
  const std::string command =
      kBinary + " " + arguments + " >" + log.string() + ".out 2>" + log.string() + ".err";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace penumbra::interchange::testing
