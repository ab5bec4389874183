// Volume objects through `penumbra` as a user runs it: `generate --volume` writes a NRRD that a
// scene can name, the bundled volume scene validates and renders, a scene whose volume file
// is broken exits 2 naming the key path, and `replay` plays volume edits (move, set_volume,
// remove, add_volume with a file beside the script) and refuses a bad one naming its line.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/cli/cli_test_support.h"

namespace {

using penumbra::cli_test::kBinary;
const std::string kVolumeRoom = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/volume_room.scene.json";

using penumbra::cli_test::runCaptured;
using penumbra::cli_test::tempPath;

std::string sceneNaming(const std::string& file) {
  return R"({"format": "penumbra.scene", "version": 1,
    "lights": [{"id": "l", "polygon": [[-1, 3, -1], [1, 3, -1], [1, 3, 1], [-1, 3, 1]], "radiance": [5, 5, 5]}],
    "objects": [{"id": "floor", "vertices": [[-3, 0, -3], [-3, 0, 3], [3, 0, 3], [3, 0, -3]], "faces": [[0, 1, 2, 3]]},
                {"id": "v", "type": "volume", "file": ")" +
         file + R"(", "isovalue": 100}]})";
}

TEST(VolumeCli, GenerateWritesAVolumeASceneCanName) {
  const std::string nrrd = tempPath("smoke.nrrd"), scene = tempPath("smoke.scene.json");
  const auto [status, text] = runCaptured("generate --volume smoke --size 20 --type ushort --out " + nrrd);
  ASSERT_EQ(status, 0) << text;
  EXPECT_NE(text.find("smoke 20³ ushort"), std::string::npos) << text;
  std::ofstream(scene) << sceneNaming(std::filesystem::path(nrrd).filename().string());
  const auto [valid, says] = runCaptured("validate " + scene);
  EXPECT_EQ(valid, 0) << says;
  EXPECT_NE(says.find("1 volumes"), std::string::npos) << says;
  EXPECT_EQ(runCaptured("generate --volume fog --out " + nrrd).first, 2);
  EXPECT_EQ(runCaptured("generate --volume smoke --type int --out " + nrrd).first, 2);
  std::filesystem::remove(nrrd);
  std::filesystem::remove(scene);
}

TEST(VolumeCli, TheBundledVolumeSceneRenders) {
  const std::string png = tempPath("room.png");
  const auto [status, text] =
      runCaptured("render " + kVolumeRoom + " --out " + png + " --width 48 --height 48");
  EXPECT_EQ(status, 0) << text;
  EXPECT_GT(std::filesystem::file_size(png), 100u);
  std::filesystem::remove(png);
}

TEST(VolumeCli, ABrokenVolumeFileExitsTwoWithTheKeyPath) {
  const std::string nrrd = tempPath("broken.nrrd"), scene = tempPath("broken.scene.json");
  std::ofstream(nrrd)
      << "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 8 8 8\nencoding: raw\n\nshort";
  std::ofstream(scene) << sceneNaming(std::filesystem::path(nrrd).filename().string());
  for (const std::string& arguments :
       {"validate " + scene, "render " + scene + " --out " + tempPath("x.png")}) {
    const auto [status, text] = runCaptured(arguments);
    EXPECT_EQ(status, 2) << text;
    EXPECT_NE(text.find("objects[1].file: 'cli_test_"), std::string::npos) << text;
    EXPECT_NE(text.find("data truncated or corrupt"), std::string::npos) << text;
  }
  std::filesystem::remove(nrrd);
  std::filesystem::remove(scene);
}

TEST(VolumeCli, ReplayPlaysVolumeEdits) {
  const std::filesystem::path dir = tempPath("volume_replay");
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/volumes/smoke64.nrrd",
                             dir / "puff.nrrd", std::filesystem::copy_options::overwrite_existing);
  const std::string script = (dir / "v.edits.jsonl").string();
  std::ofstream(script)
      << R"({"edits":[{"op":"move","id":"smoke","transform":{"translate":[1,1,3]}}]})"
         "\n"
      << R"({"edits":[{"op":"set_volume","id":"smoke","isovalue":80}]})"
         "\n"
      << R"({"edits":[{"op":"add_volume","volume":{"id":"puff","type":"volume","file":"puff.nrrd","isovalue":60}}]})"
         "\n"
      << R"({"edits":[{"op":"remove","id":"smoke"}]})"
         "\n";
  const auto [status, text] = runCaptured("replay " + kVolumeRoom + " " + script + " --verify");
  EXPECT_EQ(status, 0) << text;
  std::ofstream(script, std::ios::app)
      << R"({"edits":[{"op":"set_volume","id":"puff","isovalue":1e9}]})"
         "\n";
  const auto [refused, says] = runCaptured("replay " + kVolumeRoom + " " + script);
  EXPECT_EQ(refused, 2) << says;
  EXPECT_NE(says.find("line 5: edits[0].isovalue: "), std::string::npos) << says;
  std::filesystem::remove_all(dir);
}

}  // namespace
