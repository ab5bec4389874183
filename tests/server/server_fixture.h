// Test fixture: a real HttpServer on an ephemeral loopback port, listening on its own thread
// from construction to scope exit (then stopped and joined). One per test.
#pragma once

#include <gtest/gtest.h>
#include <httplib.h>
#include <zlib.h>

#include <chrono>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "protocol/json_text.h"
#include "protocol/scene_json.h"
#include "server/http_server.h"
#include "test_client.h"

namespace penumbra::server::test {

using nlohmann::json;

// How long a test's client waits for an answer. A GI image or an indirect bake that takes 7-8 s in
// Release took past 30 s under ASan on a loaded 2-core CI machine: the request failed with no
// answer, not with a wrong one. Tests of timeouts set their own.
inline constexpr time_t kClientReadSeconds = 180;

// How many times a build is slower than a plain one, for the few wall-clock bounds that are
// the product's promise (health within 2 s beside 500 slow sockets, a request head's deadline):
// under ThreadSanitizer every memory access is instrumented and they took 2-3× their bound in
// CI; AddressSanitizer builds meet the plain bounds and keep them. Scaled, a bound still
// catches a hang.
#if defined(__SANITIZE_THREAD__)
inline constexpr double kTimingSlowdown = 5;
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
inline constexpr double kTimingSlowdown = 5;
#else
inline constexpr double kTimingSlowdown = 1;
#endif
#else
inline constexpr double kTimingSlowdown = 1;
#endif
// `seconds` of a plain build, scaled by kTimingSlowdown.
inline std::chrono::duration<double> timingBound(double seconds) {
  return std::chrono::duration<double>(seconds * kTimingSlowdown);
}

inline std::string scenePath(const std::string& name) {
  return std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + name + ".scene.json";
}

inline std::string sceneText(const std::string& name) {
  return protocol::readTextFile(scenePath(name), protocol::kMaxJsonFileBytes);
}

class RunningServer {
 public:
  explicit RunningServer(ServerOptions options = loopback()) : server_(std::move(options)) {
    port_ = server_.bind();
    listener_ = std::thread([this] { server_.listen(); });
    // cpp-httplib 0.11 has no wait_until_ready(): poll.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!server_.isRunning()) {
      if (std::chrono::steady_clock::now() > deadline)
        throw std::runtime_error("server did not start");
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  }
  ~RunningServer() {
    server_.stop();
    listener_.join();
  }

  static ServerOptions loopback() {
    ServerOptions options;
    options.host = "127.0.0.1";
    options.port = 0;
    return options;
  }

  HttpServer& server() { return server_; }
  int port() const { return port_; }
  TestClient client() const {
    TestClient client("127.0.0.1", port_);
    client.set_read_timeout(kClientReadSeconds, 0);
    return client;
  }
  // Serves a bundled scene under the id `name`.
  std::string addBundled(const std::string& name) {
    return server_.addScene(protocol::loadSceneFile(scenePath(name)), name + ".scene.json", name);
  }

 private:
  HttpServer server_;
  int port_ = 0;
  std::thread listener_;
};

inline json bodyJson(const Reply& result) {
  if (!result) throw std::runtime_error("no HTTP response: " + httplib::to_string(result.error()));
  return json::parse(result->body);
}

// A mesh's receivers by (object, face), without the served-only "scene_version".
using ReceiverKey = std::pair<std::string, uint32_t>;
inline std::map<ReceiverKey, json> receiversByKey(const json& mesh) {
  std::map<ReceiverKey, json> out;
  for (const json& r : mesh["receivers"]) {
    json copy = r;
    copy.erase("scene_version");
    out[{r["object"].get<std::string>(), r["face"].get<uint32_t>()}] = copy;
  }
  return out;
}

inline json moveFrame(const std::string& id, double x, double y, double z, double rotateY = 0) {
  return {{"edits",
           json::array(
               {{{"op", "move"},
                 {"id", id},
                 {"transform", {{"translate", {x, y, z}}, {"rotate_deg", {0, rotateY, 0}}}}}})}};
}

inline Reply postJson(TestClient& client, const std::string& path, const json& body) {
  return client.Post(path.c_str(), body.dump(), "application/json");
}

// Each frame POSTed to scene `base` (/api/scenes/ID) is refused with 422 naming its key path; then
// the scene is still at version 0 with the lights `original`.
inline void expectLightFramesRefused(TestClient& client, const std::string& base,
                                     const std::vector<std::pair<json, std::string>>& cases,
                                     const json& original) {
  for (const auto& [frame, path] : cases) {
    const auto res = postJson(client, base + "/edits", frame);
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 422) << frame.dump() << " → " << res->body;
    EXPECT_EQ(bodyJson(res)["error"]["path"], path) << res->body;
  }
  const json scene = bodyJson(client.Get(base.c_str()));
  EXPECT_EQ(scene["version"], 0);
  EXPECT_EQ(scene["scene"]["lights"], original);
}

// The bytes of a gzip stream (what a gzip-encoded answer carries).
inline std::string gunzip(const std::string& data) {
  z_stream stream{};
  EXPECT_EQ(inflateInit2(&stream, 15 + 16), Z_OK);
  std::string out;
  char buffer[1 << 16];
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  stream.avail_in = uInt(data.size());
  int status = Z_OK;
  while (status == Z_OK) {
    stream.next_out = reinterpret_cast<Bytef*>(buffer);
    stream.avail_out = sizeof buffer;
    status = inflate(&stream, Z_NO_FLUSH);
    out.append(buffer, sizeof buffer - stream.avail_out);
  }
  EXPECT_EQ(status, Z_STREAM_END);
  inflateEnd(&stream);
  return out;
}

}  // namespace penumbra::server::test
