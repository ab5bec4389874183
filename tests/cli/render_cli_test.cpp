// `penumbra render` as a user runs it: images read back with OpenImageIO (PNG size, channels and
// the light's pixels; EXR's linear values), camera options, and refusals with exit status 2.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "tests/cli/cli_test_support.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

using penumbra::cli_test::kBinary;
using penumbra::cli_test::kCornell;

using penumbra::cli_test::runQuiet;
using penumbra::cli_test::tempPath;

struct Decoded {
  int width = 0, height = 0, channels = 0;
  std::string format;
  std::vector<float> pixels;  // as floats: 0..1 for PNG, radiance for EXR
};

Decoded decode(const std::string& path) {
  Decoded image;
  auto in = OIIO::ImageInput::open(path);
  if (!in) return image;
  const OIIO::ImageSpec& spec = in->spec();
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.nchannels;
  image.format = in->format_name();
  image.pixels.resize(size_t(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data())) image.pixels.clear();
  return image;
}

TEST(RenderCli, CornellPngDecodesAtTheRequestedSizeWithTheLightWhite) {
  const std::string out = tempPath("cornell.png");
  std::filesystem::remove(out);
  ASSERT_EQ(runQuiet("render " + kCornell + " --out " + out + " --width 64 --height 48"), 0);
  const Decoded image = decode(out);
  EXPECT_EQ(image.format, "png");
  ASSERT_EQ(image.width, 64);
  ASSERT_EQ(image.height, 48);
  ASSERT_EQ(image.channels, 3);
  ASSERT_EQ(image.pixels.size(), 64u * 48 * 3);
  // The light (y = 5.48, centred at x = 2.78) is near the top centre; it clips to white and
  // no row below the light's is white.
  int whiteRow = -1;
  for (int j = 0; j < 48 && whiteRow < 0; ++j)
    for (int i = 0; i < 64; ++i) {
      const float* p = &image.pixels[3 * (size_t(j) * 64 + i)];
      if (p[0] == 1 && p[1] == 1 && p[2] == 1) whiteRow = j;
    }
  ASSERT_GE(whiteRow, 0);
  EXPECT_LT(whiteRow, 10);
}

TEST(RenderCli, ExrHoldsLinearRadianceAndTheReferenceOptionRuns) {
  const std::string out = tempPath("cornell.exr");
  ASSERT_EQ(runQuiet("render " + kCornell + " --out " + out + " --width 40 --height 30 --reference"), 0);
  const Decoded image = decode(out);
  EXPECT_EQ(image.format, "openexr");
  ASSERT_EQ(image.width, 40);
  ASSERT_EQ(image.height, 30);
  ASSERT_EQ(image.channels, 3);
  // The light's radiance (17, 12, 4) appears unscaled; everything else is dimmer.
  float brightest = 0;
  int lightPixels = 0;
  for (size_t k = 0; k < image.pixels.size(); k += 3) {
    brightest = std::max(brightest, image.pixels[k]);
    if (image.pixels[k] == 17.0f && image.pixels[k + 1] == 12.0f && image.pixels[k + 2] == 4.0f) ++lightPixels;
  }
  EXPECT_EQ(brightest, 17.0f);
  EXPECT_GT(lightPixels, 0);
}

TEST(RenderCli, CameraOptionInlineOrFileAndAStoredMesh) {
  const std::string camera =
      R"({"position": [2.78, 8, 2.8], "target": [2.78, 0, 2.8], "up": [0, 0, 1], "projection": "orthographic", "height": 6})";
  const std::string cameraFile = tempPath("camera.json");
  std::ofstream(cameraFile) << camera;
  const std::string mesh = tempPath("cornell.mesh.json");
  ASSERT_EQ(runQuiet("build " + kCornell + " --out " + mesh), 0);
  const std::string inlineOut = tempPath("inline.png"), fileOut = tempPath("file.png");
  ASSERT_EQ(runQuiet("render " + kCornell + " --out " + inlineOut + " --width 32 --height 32 --camera '" + camera + "' --mesh " + mesh), 0);
  ASSERT_EQ(runQuiet("render " + kCornell + " --out " + fileOut + " --width 32 --height 32 --camera " + cameraFile), 0);
  const Decoded a = decode(inlineOut), b = decode(fileOut);
  ASSERT_EQ(a.width, 32);
  // Same camera, same mesh (built the same way): the same image.
  EXPECT_EQ(a.pixels, b.pixels);
  // A view from above differs from the scene's own camera.
  const std::string defaultOut = tempPath("default.png");
  ASSERT_EQ(runQuiet("render " + kCornell + " --out " + defaultOut + " --width 32 --height 32"), 0);
  EXPECT_NE(decode(defaultOut).pixels, a.pixels);
}

TEST(RenderCli, RefusesBadSizesCamerasAndExtensionsWithStatus2) {
  const std::string out = tempPath("refused.png");
  std::filesystem::remove(out);
  EXPECT_EQ(runQuiet("render " + kCornell + " --out " + out + " --width 0"), 2);
  EXPECT_EQ(runQuiet("render " + kCornell + " --out " + out + " --height 8193"), 2);
  EXPECT_EQ(runQuiet("render " + kCornell + " --out " + tempPath("refused.jpg")), 2);
  EXPECT_EQ(runQuiet("render " + kCornell), 2);
  EXPECT_EQ(runQuiet("render " + kCornell + " --out " + out + " --camera '{\"position\": [0, 0, 0], \"target\": [0, 0, 0]}'"), 2);
  EXPECT_EQ(runQuiet("render " + kCornell + " --out " + out + " --camera '{\"position\": [0, 1, 1], \"target\": [0, 0, 0], \"fov_y_deg\": 200}'"), 2);
  EXPECT_EQ(runQuiet("render " + kCornell + " --out " + out + " --camera '{not json'"), 2);
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
