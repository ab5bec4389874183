// Server-sent events over real HTTP: a stream announces the current version on connect
// and each applied frame after it; streams end when the server stops.
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>

#include "server_fixture.h"

namespace penumbra::server::test {
namespace {

// Reads an event stream on a thread until `until` matches what arrived (or the
// server ends the stream); all within the client's read timeout.
class StreamReader {
 public:
  StreamReader(const RunningServer& running, const std::string& path, std::string until)
      : client_(running.client()), until_(std::move(until)) {
    client_.set_read_timeout(10, 0);
    thread_ = std::thread([this, path] {
      client_.Get(path.c_str(), [this](const char* data, size_t size) {
        std::lock_guard lock(mutex_);
        text_.append(data, size);
        return text_.find(until_) == std::string::npos;  // false ends the read
      });
      done_ = true;
    });
  }
  ~StreamReader() {
    if (thread_.joinable()) thread_.join();
  }
  bool waitFor(const std::string& needle, std::chrono::seconds limit) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < deadline) {
      if (text().find(needle) != std::string::npos) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }
  std::string text() {
    std::lock_guard lock(mutex_);
    return text_;
  }
  void join() {
    if (thread_.joinable()) thread_.join();
  }
  bool done() const { return done_; }

 private:
  TestClient client_;
  std::string until_;
  std::mutex mutex_;
  std::string text_;
  std::atomic<bool> done_{false};
  std::thread thread_;
};

TEST(ServerEvents, StreamAnnouncesEachAppliedVersion) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  StreamReader stream(running, "/api/scenes/" + id + "/events", "\"version\":2");
  ASSERT_TRUE(stream.waitFor("\"version\":0", std::chrono::seconds(10))) << stream.text();
  EXPECT_NE(stream.text().find("event: version\ndata: "), std::string::npos);

  auto client = running.client();
  const std::string edits = "/api/scenes/" + id + "/edits";
  ASSERT_EQ(
      client
          .Post(edits.c_str(), moveFrame("tall_block", 3.9, 0, 3.6, 17).dump(), "application/json")
          ->status,
      200);
  ASSERT_TRUE(stream.waitFor("\"version\":1", std::chrono::seconds(10))) << stream.text();
  ASSERT_EQ(
      client
          .Post(edits.c_str(), moveFrame("tall_block", 3.7, 0, 3.6, 17).dump(), "application/json")
          ->status,
      200);
  stream.join();
  const std::string text = stream.text();
  // The event of version 1 names the moved block's receivers among the changed ones.
  const size_t v1 = text.find("\"version\":1");
  ASSERT_NE(v1, std::string::npos);
  const size_t start = text.rfind("data: ", v1) + 6;
  const json event = json::parse(text.substr(start, text.find('\n', start) - start));
  bool moved = false;
  for (const json& r : event["changed"]) moved |= r["object"] == "tall_block";
  EXPECT_TRUE(moved) << event.dump();
  EXPECT_NE(text.find("\"version\":2"), std::string::npos);
}

TEST(ServerEvents, StopEndsOpenStreams) {
  const auto start = std::chrono::steady_clock::now();
  auto running = std::make_unique<RunningServer>();
  const std::string id = running->addBundled("cornell");
  StreamReader a(*running, "/api/scenes/" + id + "/events", "never");
  StreamReader b(*running, "/api/scenes/" + id + "/events", "never");
  ASSERT_TRUE(a.waitFor("\"version\":0", std::chrono::seconds(10)));
  ASSERT_TRUE(b.waitFor("\"version\":0", std::chrono::seconds(10)));
  EXPECT_EQ(bodyJson(running->client().Get("/api/health"))["event_streams"], 2);
  running.reset();  // stops with both streams open: must not hang, and ends them
  a.join();
  b.join();
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(8));
}

TEST(ServerEvents, TooManyStreamsAre429) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  std::vector<std::unique_ptr<StreamReader>> streams;
  for (int i = 0; i < kMaxEventStreams; ++i) {
    streams.push_back(
        std::make_unique<StreamReader>(running, "/api/scenes/" + id + "/events", "never"));
    ASSERT_TRUE(streams.back()->waitFor("\"version\":0", std::chrono::seconds(10)));
  }
  auto client = running.client();
  const auto res = client.Get(("/api/scenes/" + id + "/events").c_str());
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 429);
  EXPECT_EQ(json::parse(res->body)["error"]["code"], "too_many_streams");
  EXPECT_EQ(client.Get("/api/health")->status, 200);  // ordinary requests still have workers
  running.server().stop();
}

}  // namespace
}  // namespace penumbra::server::test
