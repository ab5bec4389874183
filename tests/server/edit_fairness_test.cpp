// One user's heavy frames never hold up another scene's cheap edits: a frame adding a light to
// scene A waits for the heavy lane (held here by the test's own heavy work, so the order is
// certain), and meanwhile drags of scene B are applied and answered, every one of them, before
// A's frame; once the lane is free A's frame applies too.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "server_fixture.h"
#include "tiny_scene.h"

namespace penumbra::server::test {
namespace {

std::string addNamedTiny(TestClient& client, const std::string& name) {
  const auto res = postJson(client, "/api/scenes?name=" + name, tinyScene());
  EXPECT_EQ(res->status, 201) << res->body;
  return bodyJson(res)["id"];
}

json addLightFrame() {
  return {{"edits",
           {{{"op", "add_light"},
             {"light",
              {{"id", "extra"},
               {"radiance", {4, 4, 4}},
               {"polygon", {{1, 2.9, 1}, {1.5, 2.9, 1}, {1.5, 2.9, 1.5}, {1, 2.9, 1.5}}}}}}}}};
}

json moveBoxFrame(int step) {
  return {{"edits",
           {{{"op", "move"},
             {"id", "box"},
             {"transform", {{"translate", {0.05 * (step % 10), 0.5, 0}}}}}}}};
}

// The heavy lane held by the test until release() (or scope exit, so a failure cannot hang).
class HeldHeavyLane {
 public:
  explicit HeldHeavyLane(EditWorkers& workers)
      : thread_([this, &workers] {
          workers.run(
              [this] {
                std::unique_lock lock(mutex_);
                held_ = true;
                changed_.notify_all();
                changed_.wait(lock, [this] { return released_; });
              },
              true);
        }) {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return held_; });
  }
  ~HeldHeavyLane() {
    release();
    thread_.join();
  }
  void release() {
    std::lock_guard lock(mutex_);
    released_ = true;
    changed_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  bool held_ = false, released_ = false;
  std::thread thread_;
};

TEST(EditFairness, AnotherScenesDragsNeverQueueBehindAHeavyFrame) {
  RunningServer server;
  auto client = server.client();
  const std::string a = addNamedTiny(client, "a"), b = addNamedTiny(client, "b");
  HeldHeavyLane lane(server.server().editWorkers());

  std::atomic<int> heavyStatus{0};
  std::thread heavy([&] {
    auto own = server.client();
    const auto res = postJson(own, "/api/scenes/" + a + "/edits", addLightFrame());
    heavyStatus = res ? res->status : -1;
  });
  // A's frame has reached the heavy lane and waits there behind the held work.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (server.server().editWorkers().heavyQueued() < 1 &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  ASSERT_EQ(server.server().editWorkers().heavyQueued(), 1u);

  client.set_read_timeout(5, 0);  // queued behind A's frame, a drag would time out
  for (int step = 1; step <= 5; ++step) {
    const auto res = postJson(client, "/api/scenes/" + b + "/edits", moveBoxFrame(step));
    ASSERT_TRUE(res) << "drag " << step << " of scene b: " << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(bodyJson(res)["version"], step);
  }
  EXPECT_EQ(heavyStatus.load(), 0);  // still waiting for the lane
  EXPECT_EQ(server.server().editWorkers().heavyQueued(), 1u);

  lane.release();
  heavy.join();
  EXPECT_EQ(heavyStatus.load(), 200);
  const json scene = bodyJson(client.Get(("/api/scenes/" + a).c_str()));
  EXPECT_EQ(scene["version"], 1);
  EXPECT_EQ(scene["scene"]["lights"].size(), 2u);
}

}  // namespace
}  // namespace penumbra::server::test
