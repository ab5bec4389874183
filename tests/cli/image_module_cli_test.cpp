// OpenImageIO is loaded only by commands that write an image (the image module, dlopen()ed on
// first use): checked with the dynamic loader's own trace (LD_DEBUG=files), and a missing module
// fails `render` with a message naming it while `build` and `import` do not notice.
#include <gtest/gtest.h>

#include "tests/cli/cli_test_support.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace {

using penumbra::cli_test::kBinary;
using penumbra::cli_test::kCornell;
const std::string kObj = std::string(PENUMBRA_SOURCE_DIR) + "/tests/interchange/data/cornell_mm.obj";

using penumbra::cli_test::tempPath;

// Runs `environment penumbra arguments`; returns the exit status, stderr in `err`.
int run(const std::string& environment, const std::string& arguments, std::string* err) {
  const std::string errPath = tempPath("stderr.txt");
  const int status =
      std::system((environment + " " + kBinary + " " + arguments + " >/dev/null 2>" + errPath).c_str());
  std::ifstream in(errPath);
  std::stringstream text;
  text << in.rdbuf();
  *err = text.str();
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The shared libraries the loader opened, from its LD_DEBUG=files trace ("file=NAME [0];  ...").
std::set<std::string> loadedLibraries(const std::string& trace) {
  std::set<std::string> names;
  for (size_t at = trace.find("file="); at != std::string::npos; at = trace.find("file=", at + 1)) {
    const size_t end = trace.find_first_of(" \t\n", at);
    names.insert(trace.substr(at + 5, end - at - 5));
  }
  return names;
}

bool loadsImageLibrary(const std::set<std::string>& libraries) {
  for (const auto& name : libraries)
    if (name.find("OpenImageIO") != std::string::npos) return true;
  return false;
}

TEST(ImageModuleCli, HelpBuildAndImportDoNotLoadOpenImageIoRenderDoes) {
  std::string err;
  ASSERT_EQ(run("LD_DEBUG=files", "--help", &err), 0);
  const auto help = loadedLibraries(err);
  EXPECT_FALSE(loadsImageLibrary(help));
  // 44 since the PostgreSQL journal (libpq brings Kerberos, LDAP and TLS); 266 with OIIO linked.
  EXPECT_LT(help.size(), 50u) << "penumbra --help loads " << help.size() << " libraries";

  ASSERT_EQ(run("LD_DEBUG=files", "build " + kCornell + " --out " + tempPath("cornell.mesh.json"), &err), 0);
  EXPECT_FALSE(loadsImageLibrary(loadedLibraries(err)));
  ASSERT_EQ(run("LD_DEBUG=files", "import " + kObj + " --out " + tempPath("cube.scene.json"), &err), 0);
  EXPECT_FALSE(loadsImageLibrary(loadedLibraries(err)));

  ASSERT_EQ(run("LD_DEBUG=files", "render " + kCornell + " --out " + tempPath("cornell.png") +
                                      " --width 16 --height 16", &err), 0);
  EXPECT_TRUE(loadsImageLibrary(loadedLibraries(err)));
}

TEST(ImageModuleCli, MissingModuleFailsRenderBeforeItsWorkAndNamesTheModule) {
  const std::string missing = tempPath("no-such-libpenumbra_image.so");
  const std::string image = tempPath("cornell.png");
  std::filesystem::remove(image);
  std::string err;
  EXPECT_EQ(run("PENUMBRA_IMAGE_MODULE=" + missing, "render " + kCornell + " --out " + image, &err), 1);
  EXPECT_NE(err.find("cannot load the image module '" + missing + "'"), std::string::npos) << err;
  EXPECT_NE(err.find("PENUMBRA_IMAGE_MODULE"), std::string::npos) << err;
  EXPECT_EQ(err.find("casting"), std::string::npos) << "refused after building: " << err;
  EXPECT_FALSE(std::filesystem::exists(image));
  EXPECT_EQ(run("PENUMBRA_IMAGE_MODULE=" + missing, "build " + kCornell + " --out " + tempPath("m.json"), &err), 0)
      << err;
}

}  // namespace
