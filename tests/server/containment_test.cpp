// Issue 12's hostile requests over real HTTP: none ends the server, invalid UTF-8 is refused
// with 400 naming where it was, and a refused request creates or changes nothing.
#include <gtest/gtest.h>

#include <string>

#include "server_fixture.h"

namespace penumbra::server::test {
namespace {

const std::string kBad = "\xff";  // never valid in UTF-8

json expectContainedError(const Reply& res, int status, const std::string& code,
                 const std::string& path) {
  if (!res) ADD_FAILURE() << "no response: " << httplib::to_string(res.error());
  if (!res) return {};
  EXPECT_EQ(res->status, status) << res->body;
  const json body = json::parse(res->body);  // throws if the answer is not valid JSON
  EXPECT_EQ(body["error"]["code"], code) << res->body;
  EXPECT_EQ(body["error"]["path"], path) << res->body;
  return body;
}

class Containment : public ::testing::Test {
 protected:
  void SetUp() override { running_.addBundled("cornell"); }
  size_t sceneCount() { return bodyJson(client_.Get("/api/scenes"))["scenes"].size(); }
  // The server still answers: the list, and every scene in it, 200 with valid JSON.
  void expectAllServed(size_t scenes) {
    const auto list = client_.Get("/api/scenes");
    ASSERT_TRUE(list);
    ASSERT_EQ(list->status, 200) << list->body;
    const json body = json::parse(list->body);
    EXPECT_EQ(body["scenes"].size(), scenes);
    for (const json& scene : body["scenes"]) {
      const std::string base = "/api/scenes/" + scene["id"].get<std::string>();
      for (const std::string& path : {base, base + "/mesh", base + "/stats"}) {
        const auto res = client_.Get(path.c_str());
        ASSERT_TRUE(res) << path;
        EXPECT_EQ(res->status, 200) << path << ": " << res->body;
        EXPECT_TRUE(json::accept(res->body)) << path;
      }
    }
  }

  RunningServer running_;
  TestClient client_ = running_.client();
};

TEST_F(Containment, NotFoundWithInvalidUtf8PathAnswers404) {
  // The 404 body names the decoded path: it used to throw outside any try (terminate).
  const json body = expectContainedError(client_.Get("/%ff"), 404, "not_found", "(url)");
  EXPECT_NE(body["error"]["message"].get<std::string>().find("\xEF\xBF\xBD"), std::string::npos);
  expectContainedError(client_.Get("/api/%ff/%fe%80"), 404, "not_found", "(url)");
  expectContainedError(client_.Get("/api/scenes/%ff"), 404, "not_found", "(url)");
  expectAllServed(1);
}

TEST_F(Containment, InvalidUtf8QueryIs400AndCreatesNothing) {
  const std::string scene = sceneText("cornell");
  expectContainedError(client_.Post("/api/scenes?name=%ff", scene, "application/json"), 400, "invalid_utf8",
              "query.name");
  expectContainedError(client_.Get("/api/scenes/cornell/mesh?since=%ff"), 400, "invalid_utf8",
              "query.since");
  expectContainedError(client_.Post("/api/scenes?format=obj&n%ffme=1", "v 0 0 0", "text/plain"), 400,
              "invalid_utf8", "query.n\xEF\xBF\xBDme");
  expectAllServed(1);
}

TEST_F(Containment, InvalidUtf8InJsonBodyIs400NamingTheKeyPath) {
  const auto post = [&](const std::string& body) {
    return client_.Post("/api/scenes/cornell/edits", body, "application/json");
  };
  expectContainedError(post(R"({"edits": [{"op": "move", "id": "tall)" + kBad + R"("}]})"), 400,
              "invalid_utf8", "edits[0].id");
  expectContainedError(post(R"({"edits": [{"op": "move", "i)" + kBad + R"(": 1}]})"), 400, "invalid_utf8",
              "edits[0]");
  std::string scene = sceneText("cornell");
  scene.replace(scene.find("\"tall_block\""), 12, "\"tall" + kBad + "\"");
  const json body = expectContainedError(client_.Post("/api/scenes", scene, "application/json"), 400,
                                "invalid_utf8", "objects[6].id");
  EXPECT_EQ(bodyJson(client_.Get("/api/scenes/cornell"))["version"], 0);
  expectAllServed(1);
}

std::string dataText(const std::string& name) {
  return protocol::readTextFile(
      std::string(PENUMBRA_SOURCE_DIR) + "/tests/interchange/data/" + name,
      protocol::kMaxJsonFileBytes);
}

// The Cornell box OBJ + MTL (tests/interchange/data), the OBJ named `fileName` and its
// object `o floor` renamed `floorName`.
httplib::MultipartFormDataItems objForm(const std::string& fileName, const std::string& floorName) {
  std::string obj = dataText("cornell_mm.obj");
  obj.replace(obj.find("o floor\n"), 7, "o " + floorName);
  return {{"file", obj, fileName, "model/obj"},
          {"mtl", dataText("cornell_mm.mtl"), "cornell_mm.mtl", "text/plain"}};
}

// The file name is the request's: refused. Names inside the file are the file's: replaced
// (U+FFFD) and counted in the import report, so every later GET of the scene is valid JSON.
TEST_F(Containment, ObjUploadWithInvalidUtf8FileNameIs400AndNamesInsideAreReplaced) {
  expectContainedError(
      client_.Post("/api/scenes?format=obj&scale=0.001", objForm("fl" + kBad + "or.obj", "floor")),
      400, "invalid_utf8", "(form).file.filename");
  EXPECT_EQ(sceneCount(), 1u);
  expectAllServed(1);
  const auto objectName =
      client_.Post("/api/scenes?format=obj&scale=0.001", objForm("floor.obj", "fl" + kBad));
  ASSERT_TRUE(objectName);
  ASSERT_EQ(objectName->status, 201) << objectName->body;
  const json created = json::parse(objectName->body);
  EXPECT_EQ(created["import"]["repairs"]["names_with_invalid_utf8_replaced"], 1) << created.dump();
  expectAllServed(2);
}

TEST_F(Containment, SceneSentWithCurlsDefaultFormContentTypeIsCreated) {
  // `curl --data-binary @scene.json` says application/x-www-form-urlencoded; httplib's
  // form limit (8 KiB, compiled into libcpp-httplib) used to refuse it with 413.
  const std::string scene = sceneText("cubes15");
  ASSERT_GT(scene.size(), size_t(16) << 10);
  const auto res =
      client_.Post("/api/scenes?name=curl", scene, "application/x-www-form-urlencoded");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 201) << res->body.substr(0, 300);
  EXPECT_EQ(json::parse(res->body)["id"], "curl");
  expectAllServed(2);
}

}  // namespace
}  // namespace penumbra::server::test
