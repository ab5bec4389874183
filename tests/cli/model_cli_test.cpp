// `penumbra generate --model` as a user runs it: writes a scene the validator accepts and says
// how many triangles the model has and whether it is closed; bad options exit 2 naming the option.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>

#include <nlohmann/json.hpp>

#include "tests/cli/cli_test_support.h"

namespace {

using penumbra::cli_test::kBinary;

using penumbra::cli_test::runCaptured;
using penumbra::cli_test::tempPath;

TEST(ModelCli, GenerateWritesAValidSceneAndSaysWhatItWrote) {
  const std::string scene = tempPath("teapot.scene.json");
  auto [status, text] = runCaptured("generate --model teapot --triangles 1000 --rest --out " + scene);
  EXPECT_EQ(status, 0) << text;
  EXPECT_NE(text.find("992 model triangles"), std::string::npos) << text;
  EXPECT_NE(text.find("resting on the floor"), std::string::npos) << text;
  EXPECT_NE(text.find("open"), std::string::npos) << text;
  std::tie(status, text) = runCaptured("validate " + scene);
  EXPECT_EQ(status, 0) << text;

  std::tie(status, text) =
      runCaptured("generate --model torus-knot --triangles 300 --seed 2 --out " + scene);
  EXPECT_EQ(status, 0) << text;
  EXPECT_NE(text.find("floating, closed"), std::string::npos) << text;
  std::filesystem::remove(scene);
}

// `build --stats` says where the display triangles go: per scene object, summing to the mesh's;
// and how many test points refinement asked and kept.
TEST(ModelCli, BuildStatsSplitTheDisplayMeshByObject) {
  const std::string scene = tempPath("knot.scene.json"), mesh = tempPath("knot.mesh.json");
  auto [status, text] = runCaptured("generate --model torus-knot --triangles 300 --rest --out " + scene);
  ASSERT_EQ(status, 0) << text;
  const std::string stats = tempPath("stats.json");
  ASSERT_EQ(std::system((kBinary + " build " + scene + " --out " + mesh + " --threads 1 --stats >" + stats +
                         " 2>/dev/null").c_str()),
            0);
  std::ifstream in(stats);
  const nlohmann::json out = nlohmann::json::parse(in);
  const nlohmann::json& byObject = out.at("mesh").at("by_object");
  size_t receivers = 0, vertices = 0, triangles = 0;
  for (const auto& [id, entry] : byObject.items()) {
    receivers += entry.at("receivers").get<size_t>();
    vertices += entry.at("vertices").get<size_t>();
    triangles += entry.at("triangles").get<size_t>();
  }
  EXPECT_EQ(vertices, out.at("mesh").at("vertices").get<size_t>());
  EXPECT_EQ(triangles, out.at("mesh").at("triangles").get<size_t>());
  ASSERT_TRUE(byObject.contains("floor")) << byObject.dump();
  ASSERT_TRUE(byObject.contains("torus_knot")) << byObject.dump();
  EXPECT_EQ(byObject["floor"]["receivers"], 1);  // one face
  EXPECT_GT(byObject["torus_knot"]["receivers"].get<size_t>(), 10u);  // each lit face of the knot
  EXPECT_EQ(receivers, byObject["torus_knot"]["receivers"].get<size_t>() + 6);  // and the room's six
  // Refinement's test points: most pass (not kept); the kept ones are display vertices.
  const size_t asked = out.at("mesh").at("test_points"), kept = out.at("mesh").at("test_points_kept");
  EXPECT_GT(kept, 0u);
  EXPECT_LT(kept, asked);
  EXPECT_LT(kept, out.at("mesh").at("vertices").get<size_t>());
  // Unrefined (the bare fans): no test point.
  ASSERT_EQ(std::system((kBinary + " build " + scene + " --out " + mesh + " --threads 1 --mesh-tolerance 0 --stats >" +
                         stats + " 2>/dev/null").c_str()),
            0);
  std::ifstream fans(stats);
  const nlohmann::json bare = nlohmann::json::parse(fans);
  EXPECT_EQ(bare.at("mesh").at("test_points"), 0);
  EXPECT_EQ(bare.at("mesh").at("test_points_kept"), 0);
  for (const std::string& path : {scene, mesh, stats}) std::filesystem::remove(path);
}

TEST(ModelCli, BadOptionsExit2NamingTheOption) {
  const std::string scene = tempPath("bad.scene.json");
  const std::pair<const char*, const char*> cases[] = {
      {"generate --model cow --out ", "--model"},
      {"generate --model blob --triangles 10 --out ", "--triangles"},
      {"generate --model blob --triangles many --out ", "--triangles"},
      {"generate --model furnished --rest --out ", "--rest"},
      {"generate --model blob --cubes 5 --out ", "--cubes"},
      {"generate --cubes 5 --triangles 300 --out ", "--triangles"},
      {"generate --model blob", "--out"},
  };
  for (const auto& [arguments, named] : cases) {
    const auto [status, text] =
        runCaptured(std::string(arguments) + (std::string(arguments).ends_with("--out ") ? scene : ""));
    EXPECT_EQ(status, 2) << arguments << ": " << text;
    EXPECT_NE(text.find(named), std::string::npos) << arguments << ": " << text;
  }
  EXPECT_FALSE(std::filesystem::exists(scene));
}

}  // namespace
