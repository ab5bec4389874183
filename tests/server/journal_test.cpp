// The journal (README "Durability") in-process: a server on a data directory is stopped and a
// second one restores every scene at its last acknowledged version with the same mesh bytes, on
// SQLite and on PostgreSQL; a failed journal write acknowledges nothing and changes nothing
// served. (The SIGKILL test is tests/server/kill_restore.py.)
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <atomic>
#include <map>
#include <random>
#include <thread>

#include "journal_answers.h"
#include "server_fixture.h"
#include "temp_data_dir.h"
#include "test_journal.h"

namespace penumbra::server::test {
namespace {

// Seeded moves of the first cubes near where they stand; returns the acknowledged version.
uint64_t drag(TestClient& client, const std::string& id, int frames, uint32_t seed) {
  const json scene = bodyJson(client.Get(("/api/scenes/" + id).c_str()))["scene"];
  std::map<std::string, json> start;
  for (const json& object : scene["objects"])
    if (object["id"].get<std::string>().rfind("cube_", 0) == 0) start[object["id"]] = object;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  uint64_t version = 0;
  for (int i = 0; i < frames; ++i) {
    const std::string cube = "cube_" + std::to_string(rng() % 3);
    json transform = start.at(cube)["transform"];
    transform["translate"][0] = transform["translate"][0].get<double>() + jitter(rng);
    transform["translate"][2] = transform["translate"][2].get<double>() + jitter(rng);
    const json frame = {{"edits", {{{"op", "move"}, {"id", cube}, {"transform", transform}}}}};
    const auto res =
        client.Post(("/api/scenes/" + id + "/edits").c_str(), frame.dump(), "application/json");
    EXPECT_TRUE(res && res->status == 200) << (res ? res->body : "no answer");
    version = bodyJson(res)["version"];
  }
  return version;
}

// The tests that hold for every journal store.
class JournalOnEachStore : public ::testing::TestWithParam<JournalBackend> {};

INSTANTIATE_TEST_SUITE_P(Stores, JournalOnEachStore,
                         ::testing::Values(JournalBackend::Sqlite, JournalBackend::Postgres),
                         backendName);

TEST_P(JournalOnEachStore, RestartRestoresEveryScenesLastVersionWithTheSameMeshBytes) {
  const TestJournal data(GetParam());
  std::map<std::string, std::pair<uint64_t, std::string>> served;  // id → version, mesh
  {
    RunningServer first(data.durable());
    auto client = first.client();
    const std::string cubes = first.addBundled("cubes15");
    const uint64_t version = drag(client, cubes, 12, 7);
    EXPECT_EQ(version, 12u);
    served[cubes] = {version, meshBin(client, cubes)};
    // A scene created over HTTP, and one deleted (its rows go with it).
    const auto created =
        client.Post("/api/scenes?name=box", sceneText("cornell"), "application/json");
    ASSERT_EQ(created->status, 201) << created->body;
    const std::string box = bodyJson(created)["id"];
    served[box] = {0, meshBin(client, box)};
    const std::string gone = first.addBundled("cubes15");
    drag(client, gone, 2, 8);
    EXPECT_EQ(client.Delete(("/api/scenes/" + gone).c_str())->status, 204);
  }
  RunningServer second(data.durable());
  const std::vector<RestoredScene> restored = second.server().restore();
  ASSERT_EQ(restored.size(), served.size());
  auto client = second.client();
  for (const RestoredScene& scene : restored) {
    EXPECT_TRUE(scene.problem.empty()) << scene.problem;
    ASSERT_TRUE(served.count(scene.id)) << scene.id;
    EXPECT_EQ(scene.version, served[scene.id].first);
    EXPECT_EQ(bodyJson(client.Get(("/api/scenes/" + scene.id).c_str()))["version"],
              served[scene.id].first);
    EXPECT_TRUE(meshBin(client, scene.id) == served[scene.id].second) << scene.id;
  }
  // The restored scene keeps taking edits, and the next restart has those too.
  EXPECT_EQ(drag(client, "cubes15", 3, 9), 15u);
}

// The server answers while the journal's scenes come back: a scene not back yet is a 503
// `restoring` with Retry-After (not a refused connection, nor a 404), health counts it, and no
// new scene can take its id; once back it is served at its last version.
TEST_P(JournalOnEachStore, ScenesBeingRestoredAre503WhileTheServerAnswers) {
  const TestJournal data(GetParam());
  std::string cubes;
  uint64_t version = 0;
  {
    RunningServer first(data.durable());
    auto client = first.client();
    cubes = first.addBundled("cubes15");
    version = drag(client, cubes, 40, 3);
  }
  RunningServer second(data.durable());
  auto client = second.client();
  second.server().reserveJournalScenes();  // as `serve` does before it listens
  std::atomic<bool> done{false};
  std::thread restoring([&] {
    second.server().restore();
    done = true;
  });
  int restoringAnswers = 0, healthAnswers = 0;
  while (!done) {
    const auto res = client.Get(("/api/scenes/" + cubes).c_str());
    ASSERT_TRUE(res);
    if (res->status == 503) {
      EXPECT_EQ(bodyJson(res)["error"]["code"], "restoring");
      EXPECT_EQ(res->get_header_value("Retry-After"), "1");
      const json health = bodyJson(client.Get("/api/health"));
      if (!done) EXPECT_LE(health["restoring"].get<int>(), 1);
      ++healthAnswers;
      ++restoringAnswers;
      const auto taken = client.Post(("/api/scenes?name=" + cubes).c_str(), sceneText("cornell"),
                                     "application/json");
      if (taken && taken->status == 201) EXPECT_NE(bodyJson(taken)["id"], cubes);
    } else {
      EXPECT_EQ(res->status, 200) << res->body;
    }
  }
  restoring.join();
  EXPECT_GT(restoringAnswers, 0) << "the restore ended before a request saw it";
  EXPECT_GT(healthAnswers, 0);
  EXPECT_EQ(bodyJson(client.Get(("/api/scenes/" + cubes).c_str()))["version"], version);
  EXPECT_EQ(bodyJson(client.Get("/api/health"))["restoring"], 0);
}

TEST(Journal, FailedWriteAcknowledgesNothingAndUndoesTheFrame) {
  TempDataDir data;
  std::string mesh;
  {
    RunningServer running(data.durable());
    auto client = running.client();
    const std::string id = running.addBundled("cubes15");
    ASSERT_EQ(drag(client, id, 3, 11), 3u);
    mesh = meshBin(client, id);
    // Another process holds the database: the server's write times out.
    sqlite3* other = nullptr;
    ASSERT_EQ(sqlite3_open((data.str() + "/journal.sqlite3").c_str(), &other), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(other, "BEGIN EXCLUSIVE", nullptr, nullptr, nullptr), SQLITE_OK);
    json cube0;
    const json got = bodyJson(client.Get(("/api/scenes/" + id).c_str()));
    for (const json& object : got["scene"]["objects"])
      if (object["id"] == "cube_0") cube0 = object;
    json transform = cube0["transform"];
    transform["translate"][0] = transform["translate"][0].get<double>() + 0.03;
    const json frame = {{"edits", {{{"op", "move"}, {"id", "cube_0"}, {"transform", transform}}}}};
    auto res =
        client.Post(("/api/scenes/" + id + "/edits").c_str(), frame.dump(), "application/json");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 503) << res->body;
    EXPECT_EQ(bodyJson(res)["error"]["code"], "journal_failed");
    sqlite3_exec(other, "ROLLBACK", nullptr, nullptr, nullptr);
    sqlite3_close(other);
    EXPECT_EQ(bodyJson(res)["error"]["applied"], false);
    // Nothing published, and the frame was undone in the engine too (atomic frames): once the
    // journal can write again, the same frame is taken as version 4.
    EXPECT_EQ(bodyJson(client.Get(("/api/scenes/" + id).c_str()))["version"], 3);
    EXPECT_TRUE(meshBin(client, id) == mesh);
    res = client.Post(("/api/scenes/" + id + "/edits").c_str(), frame.dump(), "application/json");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 200) << res->body;
    mesh = meshBin(client, id);
  }
  RunningServer second(data.durable());
  ASSERT_EQ(second.server().restore().at(0).version, 4u);
  auto client = second.client();
  EXPECT_TRUE(meshBin(client, "cubes15") == mesh);
  EXPECT_EQ(drag(client, "cubes15", 1, 12), 5u);
}

TEST(Journal, EphemeralServerRestoresNothing) {
  RunningServer running;  // no dataDir
  EXPECT_TRUE(running.server().restore().empty());
  EXPECT_EQ(bodyJson(running.client().Get("/api/health"))["durable"], false);
}

}  // namespace
}  // namespace penumbra::server::test
