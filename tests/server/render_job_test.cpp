// Images render as jobs: a render reports its progress (polled by ticket and on the scene's event
// stream) and stops — its memory given back, the server free for the next — when its ticket is
// deleted, its client closes the request, a newer render of the same page starts, or the server
// stops. The long render: sensor GI of the 15-cube room (seconds).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <thread>

#include "server_fixture.h"

namespace penumbra::server::test {
namespace {

using Clock = std::chrono::steady_clock;

// A GI render stops at its next report: the end of a level of sensors (under a second in
// Release at this size on 2 busy cores; the thread sanitizer runs the loops on one thread, 5–10×
// slower). The answer being 409, not the image, is what shows the render stopped early.
constexpr std::chrono::seconds kStopBound{20};
constexpr int kWidth = 160, kHeight = 131;

std::string giImage(const std::string& ticket, const std::string& page = "") {
  return "/api/scenes/cubes15/image?width=" + std::to_string(kWidth) +
         "&height=" + std::to_string(kHeight) + "&gi=sensors&ticket=" + ticket +
         (page.empty() ? "" : "&page=" + page);
}

// Room for exactly one such GI image, so a second image waits (503) until the first gives its
// memory back.
ServerOptions oneGiImage() {
  ServerOptions options = RunningServer::loopback();
  options.imageMemoryBytes = uint64_t(kWidth) * kHeight * kGiImageBytesPerPixel;
  return options;
}

struct RenderAnswer {
  std::atomic<int> status{0};  // 0: none yet (or the connection closed)
  std::string body;
  Clock::time_point at;
};

std::thread startRender(int port, const std::string& path, RenderAnswer* answer, int readTimeout = 120) {
  return std::thread([=] {
    TestClient client("127.0.0.1", port);
    client.set_read_timeout(readTimeout, 0);
    const auto res = client.Get(path.c_str());
    answer->at = Clock::now();
    if (res) {
      answer->body = res->body;
      answer->status = res->status;
    }
  });
}

// The render's entry once it has placed some sensors; nullopt after 60 s.
std::optional<json> renderUnderway(TestClient& client, const std::string& ticket) {
  const auto deadline = Clock::now() + std::chrono::seconds(60);
  while (Clock::now() < deadline) {
    const auto res = client.Get(("/api/scenes/cubes15/renders/" + ticket).c_str());
    if (res && res->status == 200) {
      const json job = json::parse(res->body);
      if (job["progress"]["stage"] == "sensors" && job["progress"]["done"] > 0) return job;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return std::nullopt;
}

// Whether a small plain image renders (200) at once: the GI render's memory was given back.
bool imageMemoryFree(TestClient& client) {
  const auto res = client.Get("/api/scenes/cubes15/image?width=16&height=16");
  return res && res->status == 200;
}

// Asks for a small image of page1 until it renders (503 busy while the render it replaces still
// holds the image memory), for at most kStopBound; `query(attempt)`: each try's own query keys.
// The last answer's status.
int newerViewRenders(TestClient& client, const std::function<std::string(int)>& query) {
  const auto start = Clock::now();
  int status = 0;
  for (int attempt = 0; Clock::now() - start < kStopBound && status != 200; ++attempt) {
    const auto res =
        client.Get("/api/scenes/cubes15/image?width=16&height=16&page=page1&" + query(attempt));
    status = res ? res->status : 0;
  }
  return status;
}

TEST(RenderJobs, DeletingTheTicketStopsALongGiRenderAndFreesTheServer) {
  RunningServer running(oneGiImage());
  running.addBundled("cubes15");
  auto client = running.client();
  RenderAnswer answer;
  std::thread render = startRender(running.port(), giImage("long"), &answer);
  const auto underway = renderUnderway(client, "long");
  ASSERT_TRUE(underway) << "the render never reported its sensors";
  EXPECT_EQ((*underway)["state"], "running");
  const double fraction = (*underway)["progress"]["fraction"];
  EXPECT_GT(fraction, 0.0);
  EXPECT_LT(fraction, 1.0);
  EXPECT_FALSE(imageMemoryFree(client)) << "the running GI render should hold the image memory";

  const auto cancelled = Clock::now();
  const auto res = client.Delete("/api/scenes/cubes15/renders/long");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200) << res->body;
  EXPECT_EQ(bodyJson(res)["state"], "cancelled") << res->body;
  render.join();
  EXPECT_EQ(answer.status.load(), 409) << answer.body;
  EXPECT_EQ(json::parse(answer.body)["error"]["code"], "render_cancelled");
  EXPECT_LT(answer.at - cancelled, kStopBound);
  EXPECT_TRUE(imageMemoryFree(client));
  const auto health = client.Get("/api/health");
  ASSERT_TRUE(health);
  EXPECT_EQ(health->status, 200);
  // The ended job stays listed a while, saying why it ended.
  json listed;
  const json list = bodyJson(client.Get("/api/scenes/cubes15/renders"));
  for (const json& job : list["renders"])
    if (job["ticket"] == "long") listed = job;
  ASSERT_TRUE(listed.is_object());
  EXPECT_EQ(listed["state"], "cancelled");
  EXPECT_EQ(listed.value("reason", ""), "cancelled by DELETE");
  EXPECT_EQ(client.Delete("/api/scenes/cubes15/renders/nosuch")->status, 404);
}

TEST(RenderJobs, ClosingTheRequestStopsTheRender) {
  RunningServer running(oneGiImage());
  running.addBundled("cubes15");
  auto client = running.client();
  RenderAnswer answer;
  // The client gives up after 1 s and closes its connection.
  std::thread render = startRender(running.port(), giImage("impatient"), &answer, 1);
  render.join();
  EXPECT_EQ(answer.status.load(), 0);
  const auto closed = Clock::now();
  json job;
  while (Clock::now() - closed < kStopBound) {
    job = bodyJson(client.Get("/api/scenes/cubes15/renders/impatient"));
    if (job.contains("state") && job["state"] != "running") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_EQ(job["state"], "cancelled") << job.dump();
  EXPECT_EQ(job["reason"], "the client closed the request");
  EXPECT_TRUE(imageMemoryFree(client));
}

TEST(RenderJobs, ANewerRenderOfThePageStopsTheOlderAndTheEventStreamSaysSo) {
  RunningServer running(oneGiImage());
  running.addBundled("cubes15");
  auto client = running.client();
  // The scene's event stream, collected on a thread until the older render is reported ended.
  std::string events;
  std::atomic<bool> sawEnd{false};
  std::thread stream([&] {
    TestClient events_client("127.0.0.1", running.port());
    events_client.set_read_timeout(60, 0);
    const auto deadline = Clock::now() + std::chrono::seconds(60);
    events_client.Get("/api/scenes/cubes15/events", [&](const char* data, size_t size) {
      events.append(data, size);
      sawEnd = events.find("\"state\":\"cancelled\"") != std::string::npos;
      return !sawEnd && Clock::now() < deadline;
    });
  });
  RenderAnswer older;
  std::thread render = startRender(running.port(), giImage("older", "page1"), &older);
  ASSERT_TRUE(renderUnderway(client, "older"));
  // The newer view: a plain image, which waits for the older one's memory (503 busy until then).
  EXPECT_EQ(newerViewRenders(client,
                             [](int attempt) { return "ticket=newer" + std::to_string(attempt); }),
            200);
  render.join();
  EXPECT_EQ(older.status.load(), 409) << older.body;
  EXPECT_EQ(bodyJson(client.Get("/api/scenes/cubes15/renders/older"))["reason"],
            "a newer render from the same page");
  stream.join();
  EXPECT_TRUE(sawEnd) << events;
  EXPECT_NE(events.find("event: render"), std::string::npos);
  EXPECT_NE(events.find("\"stage\":\"sensors\""), std::string::npos) << events;
}

// A page that numbers its renders (seq) is ordered by the numbers, not by arrival: a request
// overtaken on its way (seq 1, or 2 again, arriving while seq 2 runs: sent just before the page
// aborted it) is refused at once and stops nothing; the next number stops the running render.
TEST(RenderJobs, APageIsOrderedByItsNumbersNotByArrival) {
  RunningServer running(oneGiImage());
  running.addBundled("cubes15");
  auto client = running.client();
  RenderAnswer current;
  std::thread render =
      startRender(running.port(), giImage("current", "page1") + "&seq=2", &current);
  ASSERT_TRUE(renderUnderway(client, "current"));
  for (const char* stale : {"seq=1&ticket=stale1", "seq=2&ticket=stale2"}) {
    const auto res =
        client.Get("/api/scenes/cubes15/image?width=16&height=16&page=page1&" + std::string(stale));
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 409) << res->body;
    EXPECT_EQ(bodyJson(res)["error"]["code"], "render_cancelled") << res->body;
    EXPECT_EQ(bodyJson(res)["error"]["path"], "query.seq") << res->body;
  }
  const json job = bodyJson(client.Get("/api/scenes/cubes15/renders/current"));
  EXPECT_EQ(job["state"], "running") << job.dump();
  EXPECT_EQ(job["seq"], 2);
  EXPECT_EQ(client.Get("/api/scenes/cubes15/renders/stale1")->status, 404);
  const auto unpaged = client.Get("/api/scenes/cubes15/image?width=16&height=16&seq=3");
  ASSERT_TRUE(unpaged);
  EXPECT_EQ(unpaged->status, 400);
  EXPECT_EQ(bodyJson(unpaged)["error"]["path"], "query.seq");
  // The next view: stops seq 2 (and waits for its memory: 503 busy until then).
  EXPECT_EQ(newerViewRenders(client,
                             [](int attempt) {
                               return "seq=" + std::to_string(3 + attempt) + "&ticket=next" +
                                      std::to_string(attempt);
                             }),
            200);
  render.join();
  EXPECT_EQ(current.status.load(), 409) << current.body;
  EXPECT_EQ(bodyJson(client.Get("/api/scenes/cubes15/renders/current"))["reason"],
            "a newer render from the same page");
}

TEST(RenderJobs, StoppingTheServerStopsARender) {
  RenderAnswer answer;
  std::thread render;
  Clock::time_point stopped;
  {
    RunningServer running(oneGiImage());
    running.addBundled("cubes15");
    auto client = running.client();
    render = startRender(running.port(), giImage("last"), &answer);
    ASSERT_TRUE(renderUnderway(client, "last"));
    stopped = Clock::now();
  }
  EXPECT_LT(Clock::now() - stopped, kStopBound);
  render.join();
}

}  // namespace
}  // namespace penumbra::server::test
