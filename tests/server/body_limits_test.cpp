// Request bodies are limited after decoding, whatever carries them: a gzip body inflating past
// the limit and a chunked body with no length at all are refused with 413 as they arrive
// (before, 1 MB of gzip became 2.1 GB and 300 MiB chunked were read whole), on every route and
// on paths that take no body; small gzip, chunked and form bodies still work. Images take their
// working memory from a budget: one over it is refused, concurrent ones past it get 503 busy.
#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "server/work_budget.h"
#include "tests/server/server_fixture.h"
#include "tests/server/tiny_scene.h"

namespace penumbra::server::test {
namespace {

constexpr size_t kLimit = size_t(1) << 20;

ServerOptions withBodyLimit() {
  ServerOptions options = RunningServer::loopback();
  options.maxBodyBytes = kLimit;
  return options;
}

std::string createTinyScene(TestClient& client) {
  const auto created = postJson(client, "/api/scenes?name=tiny", tinyScene());
  EXPECT_TRUE(created && created->status == 201);
  return bodyJson(created)["id"];
}

uint64_t versionOf(TestClient& client, const std::string& id) {
  return bodyJson(client.Get(("/api/scenes/" + id).c_str()))["version"];
}

// A valid frame padded with `padding` spaces (JSON whitespace) after it.
std::string paddedFrame(size_t padding) {
  return moveFrame("box", 0.1, 0.5, 0).dump() + std::string(padding, ' ');
}

void expect413(const Reply& res) {
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 413);
  const json error = bodyJson(res)["error"];
  EXPECT_EQ(error["code"], "payload_too_large");
  EXPECT_EQ(error["path"], "(body)");
}

// Sends `body` chunked (no Content-Length) in 64 KiB pieces.
Reply postChunked(TestClient& client, const std::string& path,
                            const std::string& body) {
  return client.Post(
      path.c_str(),
      [&body](size_t offset, httplib::DataSink& sink) {
        if (offset >= body.size()) {
          sink.done();
          return true;
        }
        return sink.write(body.data() + offset, std::min<size_t>(65536, body.size() - offset));
      },
      "application/json");
}

TEST(BodyLimits, GzipBodiesAreCountedInflated) {
  RunningServer running(withBodyLimit());
  auto client = running.client();
  const std::string id = createTinyScene(client);
  const std::string edits = "/api/scenes/" + id + "/edits";
  client.set_compress(true);  // the body goes gzip-compressed (Content-Encoding: gzip)
  // 8 MiB of JSON whitespace is about 8 KiB of gzip: under the limit on the wire, not inflated.
  expect413(client.Post(edits.c_str(), paddedFrame(8 * kLimit), "application/json"));
  EXPECT_EQ(versionOf(client, id), 0u);
  // A small gzip body is read and applied.
  const auto small = client.Post(edits.c_str(), paddedFrame(1000), "application/json");
  ASSERT_TRUE(small);
  EXPECT_EQ(small->status, 200) << small->body;
  client.set_compress(false);
  EXPECT_EQ(versionOf(client, id), 1u);
}

TEST(BodyLimits, ChunkedBodiesAreCountedAsTheyArrive) {
  RunningServer running(withBodyLimit());
  auto client = running.client();
  const std::string id = createTinyScene(client);
  const std::string base = "/api/scenes/" + id;
  // Every route that reads a body, one that ignores it, and a path with no route at all.
  for (const std::string path : {base + "/edits", std::string("/api/scenes"), base + "/volumes",
                                 base + "/rebuild", std::string("/api/no-such-thing")}) {
    SCOPED_TRACE(path);
    expect413(postChunked(client, path, paddedFrame(4 * kLimit)));
  }
  EXPECT_EQ(versionOf(client, id), 0u);
  const auto small = postChunked(client, base + "/edits", paddedFrame(1000));
  ASSERT_TRUE(small);
  EXPECT_EQ(small->status, 200) << small->body;
  EXPECT_EQ(versionOf(client, id), 1u);
  // A chunked body to a path without a route is read (within the limit) and answered 404.
  const auto nowhere = postChunked(client, "/api/no-such-thing", "{}");
  ASSERT_TRUE(nowhere);
  EXPECT_EQ(nowhere->status, 404);
}

TEST(BodyLimits, FormPartsCountTowardsTheLimit) {
  RunningServer running(withBodyLimit());
  auto client = running.client();
  const std::string big(kLimit + 1, '#');
  httplib::MultipartFormDataItems form = {{"file", big, "big.obj", "model/obj"}};
  expect413(client.Post("/api/scenes?format=obj", form));
  // A small form is split into its parts as before.
  const std::string tetra =
      "o tetra\nv 0 0 0\nv 100 0 0\nv 0 100 0\nv 0 0 100\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 4 3\n";
  const auto created =
      client.Post("/api/scenes?format=obj&name=tetra.obj",
                  httplib::MultipartFormDataItems{{"file", tetra, "tetra.obj", "model/obj"}});
  ASSERT_TRUE(created);
  EXPECT_EQ(created->status, 201) << created->body;
}

TEST(WorkBudget, SharesAreTakenWhileFreeAndGivenBackWhenDropped) {
  WorkBudget budget(100);
  EXPECT_TRUE(budget.fits(100));
  EXPECT_FALSE(budget.fits(101));
  {
    auto a = budget.tryTake(60);
    ASSERT_TRUE(a);
    EXPECT_FALSE(budget.tryTake(41));  // 60 + 41 > 100
    auto b = budget.tryTake(40);
    ASSERT_TRUE(b);
    EXPECT_EQ(budget.inUse(), 100u);
    auto moved = std::move(*b);  // a moved share is given back once
    b.reset();
    EXPECT_EQ(budget.inUse(), 100u);
  }
  EXPECT_EQ(budget.inUse(), 0u);
  EXPECT_FALSE(budget.tryTake(101));
  // Threads taking and dropping shares never see more than the capacity in use.
  std::atomic<bool> over{false};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&] {
      for (int i = 0; i < 20000; ++i)
        if (auto share = budget.tryTake(30))
          if (budget.inUse() > 100) over = true;
    });
  for (auto& thread : threads) thread.join();
  EXPECT_FALSE(over);
  EXPECT_EQ(budget.inUse(), 0u);
}

TEST(ImageMemory, AnImageOverTheBudgetIsRefusedAndConcurrentOnesWait) {
  ServerOptions options = RunningServer::loopback();
  options.imageMemoryBytes = uint64_t(16) << 20;  // 16 MiB: 699,050 pixels, 161,319 with GI
  RunningServer running(options);
  auto client = running.client();
  const std::string image = "/api/scenes/" + createTinyScene(client) + "/image";
  const auto tooBig = client.Get((image + "?width=1024&height=1024&samples=1").c_str());
  ASSERT_TRUE(tooBig);
  EXPECT_EQ(tooBig->status, 400);
  EXPECT_EQ(bodyJson(tooBig)["error"]["path"], "query.width");
  const auto giTooBig = client.Get((image + "?width=512&height=512&samples=1&gi=sensors").c_str());
  ASSERT_TRUE(giTooBig);
  EXPECT_EQ(giTooBig->status, 400);
  // Six at once, each taking most of the budget: one renders at a time, the rest hear 503.
  std::vector<int> statuses(6);
  std::vector<std::string> retryAfter(6);
  std::vector<std::thread> clients;
  for (size_t i = 0; i < statuses.size(); ++i)
    clients.emplace_back([&, i] {
      auto own = running.client();
      const auto res = own.Get((image + "?width=800&height=800&samples=8").c_str());
      statuses[i] = res ? res->status : -1;
      if (res) retryAfter[i] = res->get_header_value("Retry-After");
    });
  for (auto& thread : clients) thread.join();
  int ok = 0, busy = 0;
  for (size_t i = 0; i < statuses.size(); ++i) {
    if (statuses[i] == 200) ++ok;
    if (statuses[i] == 503) {
      ++busy;
      EXPECT_EQ(retryAfter[i], "1");
    }
  }
  EXPECT_EQ(ok + busy, 6);
  EXPECT_GE(ok, 1);
  EXPECT_GE(busy, 1);
  // Given back: the next one renders.
  const auto after = client.Get((image + "?width=800&height=800&samples=1").c_str());
  ASSERT_TRUE(after);
  EXPECT_EQ(after->status, 200);
}

}  // namespace
}  // namespace penumbra::server::test
