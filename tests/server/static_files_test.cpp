// The page's static files (docs/API.md "Static files"): random files served byte for byte, text
// gzip-compressed once (never brotli), an ETag per content that changes when the file does, 304
// on a matching If-None-Match, Cache-Control per mount; JSON API answers offered gzip, not br.
#include "server/static_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "server_fixture.h"

namespace penumbra::server::test {
namespace {

namespace fs = std::filesystem;


void writeFile(const fs::path& path, const std::string& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << bytes;
}

// Text that compresses (words from a small vocabulary), or random bytes that do not.
std::string randomContent(std::mt19937& rng, bool text) {
  static const char* words[] = {"const ", "three ", "mesh ",  "=> ",
                                "{ ",     "}\n",    "light ", "receiver "};
  std::string out;
  const size_t size = std::uniform_int_distribution<size_t>(0, 200000)(rng);
  while (out.size() < size)
    out += text ? std::string(words[rng() % 8]) : std::string(1, char(rng() & 0xff));
  return out;
}

struct Served {
  fs::path dir;
  RunningServer running;
  explicit Served(const fs::path& root)
      : dir(root), running([&] {
          ServerOptions options = RunningServer::loopback();
          options.staticDir = (root / "page").string();
          return options;
        }()) {}
};

fs::path freshDir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("penumbra-static-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "page");
  return dir;
}

TEST(StaticFiles, RandomFilesComeBackExactlyGzipOnceWithEtags) {
  const fs::path root = freshDir("random");
  std::mt19937 rng(20261123);
  std::vector<std::pair<std::string, std::string>> files;
  for (int i = 0; i < 12; ++i) {
    const bool text = i % 3 != 0;
    const std::string name =
        "sub" + std::to_string(i % 3) + "/f" + std::to_string(i) + (text ? ".js" : ".bin");
    files.emplace_back(name, randomContent(rng, text));
    writeFile(root / "page" / name, files.back().second);
  }
  writeFile(root / "node_modules" / "three" / "three.core.js", randomContent(rng, true) + "x");
  Served served(root);
  auto client = served.running.client();
  client.set_decompress(false);
  for (const auto& [name, bytes] : files) {
    const std::string url = "/" + name;
    const auto gz = client.Get(url.c_str(), {{"Accept-Encoding", "gzip, deflate, br"}});
    ASSERT_TRUE(gz);
    ASSERT_EQ(gz->status, 200) << name;
    const std::string encoding = gz->get_header_value("Content-Encoding");
    EXPECT_NE(encoding, "br") << name;
    EXPECT_EQ(encoding == "gzip" ? gunzip(gz->body) : gz->body, bytes) << name;
    if (name.ends_with(".js") && bytes.size() > 1000) EXPECT_EQ(encoding, "gzip") << name;
    EXPECT_EQ(gz->get_header_value("Cache-Control"), "no-cache");
    const auto plain = client.Get(url.c_str());
    ASSERT_TRUE(plain);
    EXPECT_EQ(plain->get_header_value("Content-Encoding"), "");
    EXPECT_EQ(plain->body, bytes) << name;
    const std::string etag = plain->get_header_value("ETag");
    ASSERT_FALSE(etag.empty());
    const auto again = client.Get(url.c_str(), {{"If-None-Match", etag}});
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 304) << name;
    EXPECT_TRUE(again->body.empty());
  }
  // Distinct contents, distinct ETags.
  std::set<std::string> etags;
  for (const auto& [name, bytes] : files)
    etags.insert(client.Get(("/" + name).c_str())->get_header_value("ETag"));
  EXPECT_EQ(etags.size(), files.size());
  const auto module = client.Get("/node_modules/three/three.core.js");
  ASSERT_TRUE(module);
  EXPECT_EQ(module->status, 200);
  EXPECT_NE(module->get_header_value("Cache-Control").find("max-age="), std::string::npos);
  fs::remove_all(root);
}

TEST(StaticFiles, AnEditedFileGetsANewEtagAndContent) {
  const fs::path root = freshDir("edit");
  writeFile(root / "page" / "index.html", "<!doctype html><title>one</title>");
  Served served(root);
  auto client = served.running.client();
  const auto first = client.Get("/");
  ASSERT_TRUE(first);
  EXPECT_EQ(first->body, "<!doctype html><title>one</title>");
  EXPECT_EQ(first->get_header_value("Content-Type"), "text/html; charset=utf-8");
  // A different size, so the change is seen whatever the file system's time resolution.
  writeFile(root / "page" / "index.html", "<!doctype html><title>two, longer</title>");
  const auto second = client.Get("/", {{"If-None-Match", first->get_header_value("ETag")}});
  ASSERT_TRUE(second);
  EXPECT_EQ(second->status, 200);
  EXPECT_EQ(second->body, "<!doctype html><title>two, longer</title>");
  EXPECT_NE(second->get_header_value("ETag"), first->get_header_value("ETag"));
  const auto missing = client.Get("/nope.js");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
  EXPECT_EQ(bodyJson(missing)["error"]["code"], "not_found");
  fs::remove_all(root);
}

TEST(StaticFiles, ApiAnswersAreOfferedGzipNotBrotli) {
  RunningServer running;
  running.addBundled("cubes15");
  auto client = running.client();
  client.set_decompress(false);
  const auto scene = client.Get("/api/scenes/cubes15", {{"Accept-Encoding", "br, gzip"}});
  ASSERT_TRUE(scene);
  EXPECT_EQ(scene->status, 200);
  EXPECT_EQ(scene->get_header_value("Content-Encoding"), "gzip");
  EXPECT_EQ(json::parse(gunzip(scene->body))["id"], "cubes15");
  const auto brOnly = client.Get("/api/scenes/cubes15", {{"Accept-Encoding", "br"}});
  ASSERT_TRUE(brOnly);
  EXPECT_EQ(brOnly->get_header_value("Content-Encoding"), "");
  EXPECT_EQ(json::parse(brOnly->body)["id"], "cubes15");
}

TEST(StaticFiles, ContentTypesByExtension) {
  EXPECT_EQ(contentTypeFor("a/b.mjs"), "text/javascript");
  EXPECT_EQ(contentTypeFor("x.glb"), "model/gltf-binary");
  EXPECT_EQ(contentTypeFor("x.wasm"), "application/wasm");
  EXPECT_EQ(contentTypeFor("x.unknown"), "application/octet-stream");
}

}  // namespace
}  // namespace penumbra::server::test
