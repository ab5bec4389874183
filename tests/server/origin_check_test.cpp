// Browsers cannot be used against the server (issue 36, item 6): a page of another origin gets
// 403 for any write, with or without a token-less default, and a loopback server refuses a Host
// that names anything but loopback (DNS rebinding); its own page, scripts without an Origin and
// allowed origins go on. No CORS header is ever sent.
#include <gtest/gtest.h>

#include <string>

#include "tests/server/server_fixture.h"

namespace penumbra::server::test {
namespace {

const char* kFrame = R"({"edits": [{"op": "move", "id": "cube_3", "transform": {"translate": [0.1, 0.5, 0]}}]})";

TEST(OriginCheck, ForeignPagesCannotWriteAndRebindingHostsAreRefused) {
  RunningServer running;
  const std::string id = running.addBundled("cubes15");
  auto client = running.client();
  const std::string edits = "/api/scenes/" + id + "/edits";
  const std::string self = "127.0.0.1:" + std::to_string(running.port());

  // A foreign page's text/plain POST (a "simple" request, no preflight): refused, nothing applied.
  auto foreign = client.Post(edits.c_str(), httplib::Headers{{"Origin", "http://evil.example"}}, kFrame, "text/plain");
  ASSERT_TRUE(foreign);
  EXPECT_EQ(foreign->status, 403);
  EXPECT_EQ(bodyJson(foreign)["error"]["path"], "(header).Origin");
  EXPECT_FALSE(foreign->has_header("Access-Control-Allow-Origin"));
  auto del = client.Delete(("/api/scenes/" + id).c_str(), httplib::Headers{{"Origin", "null"}});
  ASSERT_TRUE(del);
  EXPECT_EQ(del->status, 403);
  auto scene = client.Get(("/api/scenes/" + id).c_str());
  ASSERT_TRUE(scene);
  EXPECT_EQ(bodyJson(scene)["version"], 0);

  // The server's own page (Origin = http:// + Host) and scripts without an Origin write.
  auto own = client.Post(edits.c_str(), httplib::Headers{{"Origin", "http://" + self}}, kFrame, "application/json");
  ASSERT_TRUE(own);
  EXPECT_EQ(own->status, 200) << own->body;
  auto script = client.Post(edits.c_str(), kFrame, "application/json");
  ASSERT_TRUE(script);
  EXPECT_EQ(script->status, 200) << script->body;

  // DNS rebinding: a name resolving to 127.0.0.1 arrives with its own Host; reads too.
  auto rebound = client.Get(("/api/scenes/" + id).c_str(), httplib::Headers{{"Host", "evil.example:" + std::to_string(running.port())}});
  ASSERT_TRUE(rebound);
  EXPECT_EQ(rebound->status, 403);
  EXPECT_EQ(bodyJson(rebound)["error"]["path"], "(header).Host");
  for (const std::string host : {"localhost", "127.0.0.1", "[::1]"}) {
    auto fine = client.Get("/api/health", httplib::Headers{{"Host", host + ":" + std::to_string(running.port())}});
    ASSERT_TRUE(fine);
    EXPECT_EQ(fine->status, 200) << host;
  }
}

TEST(OriginCheck, AllowedOriginsMayWrite) {
  ServerOptions options = RunningServer::loopback();
  options.allowedOrigins = {"http://dev.example:5173"};
  RunningServer running(options);
  const std::string id = running.addBundled("cubes15");
  auto client = running.client();
  auto allowed = client.Post(("/api/scenes/" + id + "/edits").c_str(),
                             httplib::Headers{{"Origin", "http://dev.example:5173"}}, kFrame, "application/json");
  ASSERT_TRUE(allowed);
  EXPECT_EQ(allowed->status, 200) << allowed->body;
  auto other = client.Post(("/api/scenes/" + id + "/edits").c_str(),
                           httplib::Headers{{"Origin", "http://dev.example:5174"}}, kFrame, "application/json");
  ASSERT_TRUE(other);
  EXPECT_EQ(other->status, 403);
}

}  // namespace
}  // namespace penumbra::server::test
