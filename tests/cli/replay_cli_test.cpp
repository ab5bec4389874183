// `penumbra replay` as a user runs it: a shipped script on scenes/cubes15 with
// --verify and --report, a script with a bad line, an unknown id in frame 3.
#include <gtest/gtest.h>

#include "tests/cli/cli_test_support.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace {

using nlohmann::json;

using penumbra::cli_test::kBinary;
const std::string kScene = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cubes15.scene.json";
const std::string kScripts = std::string(PENUMBRA_SOURCE_DIR) + "/bench/edits/";

using penumbra::cli_test::tempPath;

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Runs penumbra with the arguments; returns the exit status, stderr in `err`.
int run(const std::string& arguments, std::string* err = nullptr) {
  const std::string errPath = tempPath("stderr.txt");
  const int status = std::system((kBinary + " " + arguments + " >/dev/null 2>" + errPath).c_str());
  if (err) *err = readFile(errPath);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(line);
  return out;
}

TEST(ReplayCli, ShippedScriptVerifiesAndReportsEveryFrame) {
  const std::string script = kScripts + "cubes15.move-10pct.edits.jsonl";
  const std::string report = tempPath("report.json"), mesh = tempPath("final.mesh.json");
  std::filesystem::remove(report);
  std::filesystem::remove(mesh);
  std::string err;
  ASSERT_EQ(
      run("replay " + kScene + " " + script + " --verify --report " + report + " --out " + mesh,
          &err),
      0)
      << err;
  const json out = json::parse(readFile(report));
  const size_t frames = lines(readFile(script)).size();
  ASSERT_EQ(out["frames"].size(), frames);
  for (size_t i = 0; i < frames; ++i) {
    const json& f = out["frames"][i];
    EXPECT_EQ(f["frame"], i + 1);
    EXPECT_EQ(f["line"], i + 1);
    EXPECT_EQ(f["version"], i + 1);
    for (const char* key : {"remove", "add", "relight", "total"})
      EXPECT_TRUE(f["seconds"][key].is_number()) << key;
    for (const char* key : {"relit", "changed", "created"})
      EXPECT_TRUE(f["vertices"][key].is_number()) << key;
    EXPECT_TRUE(f["changed_receivers_count"].is_number());
    EXPECT_TRUE(f["tree_rebuilds"].is_number());
    EXPECT_EQ(f["full_rebuild"], false);  // 96 faces: below the full-rebuild threshold
    EXPECT_EQ(f["verified"], true);  // 96 faces: every frame
    EXPECT_GT(f["rebuild_seconds"].get<double>(), 0);
    EXPECT_TRUE(f["edit_over_rebuild"].is_number());
    EXPECT_GE(f["vertices"]["relit"].get<size_t>(), f["vertices"]["changed"].get<size_t>());
  }
  EXPECT_EQ(out["totals"]["frames"], frames);
  EXPECT_EQ(out["totals"]["verified_frames"], frames);
  EXPECT_EQ(out["totals"]["full_rebuild_frames"], 0);
  EXPECT_TRUE(out["verify_failure"].is_null());
  const json meshJson = json::parse(readFile(mesh));
  EXPECT_EQ(meshJson["format"], "penumbra.mesh");
  EXPECT_FALSE(meshJson["receivers"].empty());
}

// The scripts that add and remove objects (the move path is verified above), with
// --verify-every 4 (the last frame is always verified).
TEST(ReplayCli, AddRemoveScriptsVerify) {
  for (const char* name : {"cubes15.remove-add.edits.jsonl", "cubes15.build-up.edits.jsonl"}) {
    const std::string report = tempPath("add_remove_report.json");
    std::string err;
    EXPECT_EQ(
        run("replay " + kScene + " " + kScripts + name + " --verify-every 4 --report " + report,
            &err),
        0)
        << name << ": " << err;
    const json out = json::parse(readFile(report));
    EXPECT_EQ(out["frames"].size(), lines(readFile(kScripts + name)).size()) << name;
    EXPECT_TRUE(out["frames"].back()["verified"].get<bool>()) << name;
  }
}

// Writes a script of the given lines; returns its path.
std::string writeScript(const std::string& name, const std::vector<std::string>& frames) {
  const std::string path = tempPath(name);
  std::ofstream out(path);
  for (const std::string& f : frames) out << f << "\n";
  return path;
}

const char* kMove =
    R"({"edits":[{"op":"move","id":"cube_3","transform":{"translate":[0.1,0.2,0.3]}}]})";

TEST(ReplayCli, BadLineExits2NamingLineAndKeyPathAndChangesNothing) {
  const std::string before = readFile(kScene);
  const std::string report = tempPath("bad_report.json"), mesh = tempPath("bad.mesh.json");
  std::filesystem::remove(report);
  std::filesystem::remove(mesh);
  const std::string script = writeScript(
      "bad.edits.jsonl",
      {kMove, "", kMove, R"({"edits":[{"op":"move","id":"cube_3","transform":{"scale":[1,0,1]}}]})",
       kMove});
  std::string err;
  EXPECT_EQ(run("replay " + kScene + " " + script + " --report " + report + " --out " + mesh, &err),
            2);
  EXPECT_NE(err.find("line 4: edits[0].transform.scale: "), std::string::npos) << err;
  EXPECT_EQ(readFile(kScene), before);
  EXPECT_FALSE(std::filesystem::exists(report));
  EXPECT_FALSE(std::filesystem::exists(mesh));

  const std::string syntax = writeScript("syntax.edits.jsonl", {kMove, "{\"edits\": [}"});
  EXPECT_EQ(run("replay " + kScene + " " + syntax, &err), 2);
  EXPECT_NE(err.find("line 2: (json): "), std::string::npos) << err;
}

TEST(ReplayCli, UnknownIdInFrame3IsRefusedNamingLine3) {
  const std::string report = tempPath("unknown_report.json");
  std::filesystem::remove(report);
  const std::string script = writeScript(
      "unknown.edits.jsonl",
      {kMove, kMove,
       R"({"edits":[{"op":"move","id":"cube_3","transform":{}},{"op":"remove","id":"ghost"}]})",
       kMove});
  std::string err;
  EXPECT_EQ(run("replay " + kScene + " " + script + " --report " + report, &err), 2);
  EXPECT_NE(err.find("line 3: edits[1].id: unknown object 'ghost'"), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(report));

  // A duplicate add id (the object is still there after frame 1) is the engine's refusal too.
  const std::string cube = readFile(kScripts + "cubes15.remove-add.edits.jsonl");
  const std::vector<std::string> removeAdd = lines(cube);
  ASSERT_GE(removeAdd.size(), 2u);
  const std::string duplicate = writeScript("duplicate.edits.jsonl", {kMove, removeAdd[1]});
  EXPECT_EQ(run("replay " + kScene + " " + duplicate, &err), 2);
  EXPECT_NE(err.find("line 2: edits[0].object.id: duplicate object id"), std::string::npos) << err;
}

TEST(ReplayCli, UsageErrors) {
  std::string err;
  EXPECT_EQ(run("replay " + kScene, &err), 2);
  EXPECT_NE(err.find("EDITS.jsonl"), std::string::npos) << err;
  EXPECT_EQ(
      run("replay " + kScene + " " + kScripts + "cubes15.drag.edits.jsonl --verify-every 0", &err),
      2);
  EXPECT_EQ(run("replay " + kScene + " /nonexistent.edits.jsonl", &err), 1);
}

}  // namespace
