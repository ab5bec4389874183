// The CLI's progress bars (cli/progress_bar.h): a bar shows its step as it rises, a quiet bar
// shows nothing while its step is younger than its quiet time (the build's brief steps), and the
// build's bars leave a room's ordering, cube and receivers steps out of the output.
#include "cli/progress_bar.h"

#include <gtest/gtest.h>

#include <string>

#include "tests/cli/cli_test_support.h"

namespace penumbra::cli {
namespace {

std::string barOutput(double quietSeconds) {
  testing::internal::CaptureStderr();
  {
    ProgressBar bar("ordering", quietSeconds);
    for (size_t done = 0; done <= 4; ++done) bar.update(done, 4);
  }
  return testing::internal::GetCapturedStderr();
}

TEST(ProgressBar, AQuietBarShowsNothingWithinItsQuietTime) {
  EXPECT_NE(barOutput(0).find("ordering"), std::string::npos);
  EXPECT_NE(barOutput(0).find("100%"), std::string::npos);
  EXPECT_EQ(barOutput(1e9), "") << "a step younger than its quiet time printed";
}

TEST(ProgressBar, ARoomsBuildShowsNoBriefSteps) {
  const auto [status, output] = cli_test::runCaptured("build " + cli_test::kCornell + " --out /dev/null");
  ASSERT_EQ(status, 0) << output;
  EXPECT_NE(output.find("casting"), std::string::npos) << output;
  for (const char* step : {"ordering:", "ordering [", "cube:", "cube [", "receivers:", "receivers ["})
    EXPECT_EQ(output.find(step), std::string::npos) << step << " shown for the Cornell box: " << output;
}

}  // namespace
}  // namespace penumbra::cli
