// The microfacet bench's error measures: masked MSE and mean, time to reach an error on a
// ladder (interpolated and extrapolated log–log), the heat map's ramp.
#include "bench/lib/image_error.h"

#include <gtest/gtest.h>

#include <cmath>

namespace penumbra {
namespace {

TEST(ImageError, MaskedMeanAndSquaredError) {
  const std::vector<float> image{1, 2, 3, 10, 10, 10}, reference{1, 2, 5, 0, 0, 0};
  const std::vector<uint8_t> mask{1, 0};
  EXPECT_DOUBLE_EQ(meanSquaredError(image, reference, mask), 4.0 / 3);
  EXPECT_DOUBLE_EQ(maskedMean(image, mask), 2.0);
}

TEST(ImageError, TimeToReachFollowsThePowerLawBetweenAndBeyondRungs) {
  // rms = t^-1/2: t(rms) = rms^-2.
  std::vector<LadderPoint> ladder;
  for (double t : {1.0, 4.0, 16.0}) ladder.push_back({0, t, 1 / std::sqrt(t)});
  const auto inside = timeToReach(ladder, 1 / std::sqrt(8.0));
  ASSERT_TRUE(inside);
  EXPECT_NEAR(inside->seconds, 8.0, 1e-9);
  EXPECT_FALSE(inside->extrapolated);
  const auto beyond = timeToReach(ladder, 1 / std::sqrt(64.0));
  ASSERT_TRUE(beyond);
  EXPECT_NEAR(beyond->seconds, 64.0, 1e-9);
  EXPECT_TRUE(beyond->extrapolated);
  // Above the first rung's error: the first rung's time, flagged.
  const auto above = timeToReach(ladder, 2.0);
  ASSERT_TRUE(above);
  EXPECT_EQ(above->seconds, 1.0);
  EXPECT_TRUE(above->firstRung);
  EXPECT_FALSE(timeToReach({ladder[0]}, 0.5));
}

TEST(ImageError, HeatMapRampAndUnmaskedGrey) {
  const std::vector<float> image{0, 0, 0, 2, 2, 2, 9, 9, 9}, reference(9, 0.0f);
  const auto map = errorHeatMap(image, reference, {1, 1, 0}, 2.0);
  EXPECT_EQ(map[0], 0);                                        // no error: black
  for (int c = 3; c < 6; ++c) EXPECT_EQ(map[size_t(c)], 255);  // at the scale: white
  EXPECT_EQ(map[6], 40);                                       // unmasked: grey
}

}  // namespace
}  // namespace penumbra
