// Who may do what (README "HTTP server"): no token off loopback is refused at start; with a token
// every mutating request needs it (401 JSON otherwise); the scene and body limits are options
// with clear errors; static files never come from outside their folder (raw request paths).
#include <gtest/gtest.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "server_fixture.h"

namespace penumbra::server::test {
namespace {

namespace fs = std::filesystem;

void expectAccessError(const Reply& res, int status, const std::string& code) {
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, status) << res->body;
  EXPECT_EQ(bodyJson(res)["error"]["code"], code) << res->body;
}

TEST(Access, ListeningOffLoopbackNeedsAToken) {
  ServerOptions options = RunningServer::loopback();
  options.host = "0.0.0.0";
  EXPECT_THROW(HttpServer{options}, std::invalid_argument);
  options.token = "s3cret";
  EXPECT_NO_THROW(HttpServer{options});
  EXPECT_TRUE(isLoopbackHost("127.0.0.1"));
  EXPECT_TRUE(isLoopbackHost("localhost"));
  EXPECT_FALSE(isLoopbackHost("192.168.1.2"));
}

TEST(Access, EveryMutatingRequestNeedsTheToken) {
  ServerOptions options = RunningServer::loopback();
  options.token = "s3cret";
  RunningServer running(options);
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const std::string scene = sceneText("cornell");
  const std::string frame = moveFrame("short_block", 0, 0, 0).dump();
  const std::string edits = "/api/scenes/" + id + "/edits";
  expectAccessError(client.Post("/api/scenes", scene, "application/json"), 401, "unauthorized");
  expectAccessError(client.Post(edits.c_str(), frame, "application/json"), 401, "unauthorized");
  expectAccessError(client.Delete(("/api/scenes/" + id).c_str()), 401, "unauthorized");
  expectAccessError(client.Post(("/api/scenes/" + id + "/rebuild").c_str(), "", "application/json"), 401,
              "unauthorized");
  expectAccessError(client.Put("/api/scenes", scene, "application/json"), 401, "unauthorized");
  expectAccessError(client.Post(("/api/scenes/" + id + "/volumes").c_str(), "NRRD0004\n",
                          "application/octet-stream"),
              401, "unauthorized");
  httplib::Headers wrong = {{"Authorization", "Bearer s3cre"}};
  expectAccessError(client.Post(edits.c_str(), wrong, frame, "application/json"), 401, "unauthorized");
  // Nothing changed; reads need no token.
  const json got = bodyJson(client.Get(("/api/scenes/" + id).c_str()));
  EXPECT_EQ(got["version"], 0);
  EXPECT_EQ(bodyJson(client.Get("/api/scenes"))["scenes"].size(), 1u);
  client.set_bearer_token_auth("s3cret");
  EXPECT_EQ(client.Post("/api/scenes", scene, "application/json")->status, 201);
  EXPECT_EQ(client.Delete(("/api/scenes/" + id).c_str())->status, 204);
}

TEST(Access, SceneAndBodyLimitsAreOptions) {
  ServerOptions options = RunningServer::loopback();
  options.maxScenes = 2;
  options.maxBodyBytes = size_t(1) << 20;
  RunningServer running(options);
  auto client = running.client();
  const json limits = bodyJson(client.Get("/api/health"))["limits"];
  EXPECT_EQ(limits["max_scenes"], 2);
  EXPECT_EQ(limits["max_body_bytes"], 1 << 20);
  const std::string scene = sceneText("cornell");
  EXPECT_EQ(client.Post("/api/scenes", scene, "application/json")->status, 201);
  EXPECT_EQ(client.Post("/api/scenes", scene, "application/json")->status, 201);
  const auto third = client.Post("/api/scenes", scene, "application/json");
  expectAccessError(third, 429, "too_many_scenes");
  EXPECT_NE(bodyJson(third)["error"]["message"].get<std::string>().find("--max-scenes"),
            std::string::npos);
  // One byte over the limit: refused before it is parsed, naming the limit.
  const std::string big = scene + std::string((size_t(1) << 20) + 1 - scene.size(), ' ');
  const auto tooBig = client.Post("/api/scenes", big, "application/json");
  expectAccessError(tooBig, 413, "payload_too_large");
  EXPECT_NE(bodyJson(tooBig)["error"]["message"].get<std::string>().find("1048576"),
            std::string::npos);
}

// Sends `target` verbatim (no client-side normalisation) and returns the whole answer.
std::string rawGet(int port, const std::string& target) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(uint16_t(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    close(fd);
    return "";
  }
  const std::string request = "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
  (void)!write(fd, request.data(), request.size());
  std::string answer;
  char buffer[4096];
  for (ssize_t n; (n = read(fd, buffer, sizeof buffer)) > 0;) answer.append(buffer, size_t(n));
  close(fd);
  return answer;
}

TEST(Access, StaticFilesNeverComeFromOutsideTheirFolder) {
  // site/web_client (the page), site/node_modules (mounted too), site/README.md and a file
  // outside site/ that must never be served, and symlinks pointing at them.
  const fs::path root = fs::temp_directory_path() / ("penumbra-access-" + std::to_string(getpid()));
  fs::remove_all(root);
  const fs::path site = root / "site";
  fs::create_directories(site / "web_client");
  fs::create_directories(site / "node_modules" / "three");
  std::ofstream(site / "web_client" / "index.html") << "PAGE";
  std::ofstream(site / "node_modules" / "three" / "three.js") << "THREE";
  std::ofstream(site / "README.md") << "SECRET-README";
  std::ofstream(root / "outside.txt") << "SECRET-OUTSIDE";
  fs::create_symlink(site / "README.md", site / "web_client" / "leak.md");
  fs::create_symlink(root, site / "web_client" / "up");
  fs::create_symlink(root / "outside.txt", site / "node_modules" / "evil.js");

  ServerOptions options = RunningServer::loopback();
  options.staticDir = (site / "web_client").string();
  RunningServer running(options);
  EXPECT_NE(rawGet(running.port(), "/index.html").find("PAGE"), std::string::npos);
  EXPECT_NE(rawGet(running.port(), "/node_modules/three/three.js").find("THREE"), std::string::npos);
  for (const char* target :
       {"/../README.md", "/%2e%2e/README.md", "/%2E%2E/README.md", "/..%2fREADME.md",
        "/%2e%2e%2fREADME.md", "/node_modules/../../README.md", "/node_modules/../../../outside.txt",
        "/node_modules/%2e%2e/%2e%2e/README.md", "/node_modules/..%2f..%2fREADME.md",
        "/leak.md", "/up/outside.txt", "/up/site/README.md", "/node_modules/evil.js",
        "/..\\README.md", "/%5c..%5cREADME.md", "/./../README.md", "//../README.md",
        "/web_client/../README.md", "/index.html/../../README.md"}) {
    const std::string answer = rawGet(running.port(), target);
    EXPECT_EQ(answer.find("SECRET"), std::string::npos) << target << "\n" << answer;
    EXPECT_EQ(answer.rfind("HTTP/1.1 200", 0), std::string::npos) << target << "\n" << answer;
  }
  fs::remove_all(root);
}

}  // namespace
}  // namespace penumbra::server::test
