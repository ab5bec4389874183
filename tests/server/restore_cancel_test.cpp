// A restore is a cancellable job, like a build: a DELETE of a scene while it comes back from the
// journal ends the restore at once and the scene leaves the journal as any DELETE removes it; a
// stop ends the restore within the stop bound, the journal unchanged, and the next start brings
// the scene back at the same version with the same mesh. On SQLite the start-up restore; on
// PostgreSQL a node restoring the scene on request (`--restore on-request`). The scene: 150
// seeded cubes, whose floor's refined display mesh makes its build (so its restore) take seconds.
#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/engine/seconds_since.h"
#include "journal_answers.h"
#include "scenegen/cubes_scene.h"
#include "server_fixture.h"
#include "test_journal.h"

namespace penumbra::server::test {
namespace {

using Clock = std::chrono::steady_clock;

// What SIGTERM must meet: the server ended within 5 s.
constexpr double kStopBoundSeconds = 5;

class RestoreCancel : public ::testing::TestWithParam<JournalBackend> {
 protected:
  // On PostgreSQL a node of a cluster: scenes come back when first asked for.
  ServerOptions options(const TestJournal& data) const {
    ServerOptions options = data.durable();
    if (GetParam() == JournalBackend::Postgres) {
      options.nodeId = "node";
      options.restoreAtStart = false;
    }
    return options;
  }

  // Journals the cubes and three frames moving one of them; remembers what was served.
  void journalCubes(const TestJournal& data) {
    RunningServer first(options(data));
    CubesSceneOptions cubes;
    cubes.cubes = 150;
    const auto start = Clock::now();
    id_ = first.server().addScene(makeCubesScene(cubes), "cubes150", "cubes150");
    buildSeconds_ = secondsSince(start);
    TestClient client = first.client();
    const json scene = bodyJson(client.Get(("/api/scenes/" + id_).c_str()))["scene"];
    json transform;
    for (const json& object : scene["objects"])
      if (object["id"] == "cube_0") transform = object["transform"];
    for (int i = 1; i <= 3; ++i) {
      transform["translate"][0] = transform["translate"][0].get<double>() + 0.02;
      const json frame = {{"edits", {{{"op", "move"}, {"id", "cube_0"}, {"transform", transform}}}}};
      const auto res = postJson(client, "/api/scenes/" + id_ + "/edits", frame);
      ASSERT_TRUE(res && res->status == 200) << (res ? res->body : "no answer");
      version_ = bodyJson(res)["version"];
    }
    mesh_ = meshBin(client, id_);
    frames_ = data.sqlText("SELECT version FROM frames ORDER BY version");
    ASSERT_EQ(frames_, "1,2,3");
  }

  // Starts the restore of the journaled scene on `server` and returns once it is under way (a
  // quarter of the first build's time in): on SQLite restore() on a thread (its reports in
  // `reports`), on PostgreSQL a GET of the scene whose request restores it (its status in
  // `status`, 0 when none came).
  std::thread startRestore(RunningServer& server, std::vector<RestoredScene>& reports, int& status) {
    std::thread restoring;
    if (GetParam() == JournalBackend::Sqlite) {
      server.server().reserveJournalScenes();  // as `serve` does before it listens
      restoring = std::thread([&server, &reports] { reports = server.server().restore(); });
    } else {
      restoring = std::thread([&status, port = server.port(), id = id_] {
        TestClient client("127.0.0.1", port);
        client.set_read_timeout(120, 0);
        if (const auto res = client.Get(("/api/scenes/" + id).c_str())) status = res->status;
      });
    }
    TestClient client = server.client();
    const auto deadline = Clock::now() + std::chrono::seconds(30);
    while (bodyJson(client.Get("/api/health"))["restoring"] != 1 && Clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    std::this_thread::sleep_for(std::chrono::duration<double>(buildSeconds_ / 4));
    const auto res = client.Get(("/api/scenes/" + id_).c_str());
    EXPECT_EQ(res->status, 503) << "the restore ended before it was cancelled (" << res->body << ")";
    EXPECT_EQ(bodyJson(res)["error"]["code"], "restoring");
    return restoring;
  }

  // The restore ended within its bound (`seconds` after the cancel), long before it could have
  // ended by itself, and whoever asked for it heard so: the start-up restore's one report says
  // the scene was not served; the GET that restored on request answered `status`.
  void expectCancelled(double seconds, const std::vector<RestoredScene>& reports, int status, int expected) const {
    EXPECT_LT(seconds, std::min(kStopBoundSeconds, buildSeconds_ / 2)) << "the first build took " << buildSeconds_ << " s";
    if (GetParam() == JournalBackend::Sqlite) {
      ASSERT_EQ(reports.size(), 1u);
      EXPECT_FALSE(reports[0].served);
    } else {
      EXPECT_EQ(status, expected);
    }
  }

  std::string id_, mesh_, frames_;
  uint64_t version_ = 0;
  double buildSeconds_ = 0;
};

INSTANTIATE_TEST_SUITE_P(Stores, RestoreCancel,
                         ::testing::Values(JournalBackend::Sqlite, JournalBackend::Postgres),
                         backendName);

TEST_P(RestoreCancel, ADeleteEndsTheRestoreAndTheSceneLeavesTheJournal) {
  const TestJournal data(GetParam());
  journalCubes(data);
  std::vector<RestoredScene> reports;
  int status = 0;
  double deleteSeconds = 0;
  {
    RunningServer second(options(data));
    std::thread restoring = startRestore(second, reports, status);
    TestClient client = second.client();
    const auto start = Clock::now();
    const auto deleted = client.Delete(("/api/scenes/" + id_).c_str());
    deleteSeconds = secondsSince(start);
    ASSERT_TRUE(deleted);
    EXPECT_EQ(deleted->status, 204) << deleted->body;
    restoring.join();
    // Gone at once, and the server serves on: the id answers 404 and is free for a new scene.
    EXPECT_EQ(client.Get(("/api/scenes/" + id_).c_str())->status, 404);
    const json health = bodyJson(client.Get("/api/health"));
    EXPECT_EQ(health["restoring"], 0);
    EXPECT_EQ(health["status"], "ok") << health.dump();
    EXPECT_EQ(second.addBundled("cubes15"), "cubes15");
  }
  RecordProperty("delete_ms", int(deleteSeconds * 1000));
  // Answered long before the restore (a build of the scene and three frames) could have ended;
  // the request whose restore the DELETE ended answers 404.
  ASSERT_NO_FATAL_FAILURE(expectCancelled(deleteSeconds, reports, status, 404));
  if (GetParam() == JournalBackend::Sqlite) {
    EXPECT_EQ(reports[0].problem, "deleted while it was being restored");
  }
  // Its rows went as a DELETE removes them; the next start has nothing of it.
  EXPECT_EQ(data.sqlText("SELECT COUNT(*) FROM scenes WHERE id = '" + id_ + "'"), "0");
  EXPECT_EQ(data.sqlText("SELECT COUNT(*) FROM frames"), "0");
  RunningServer third(options(data));
  third.server().restore();
  TestClient client = third.client();
  EXPECT_EQ(client.Get(("/api/scenes/" + id_).c_str())->status, 404);
}

TEST_P(RestoreCancel, AStopEndsTheRestoreWithinItsBoundAndTheNextStartRestoresEverything) {
  const TestJournal data(GetParam());
  journalCubes(data);
  std::vector<RestoredScene> reports;
  int status = 0;
  double stopSeconds = 0;
  {
    std::thread restoring;
    std::optional<Clock::time_point> start;
    {
      RunningServer second(options(data));
      restoring = startRestore(second, reports, status);
      start = Clock::now();
      second.server().stop();
      restoring.join();
    }  // the listener joined: every request ended
    stopSeconds = secondsSince(*start);
  }
  RecordProperty("stop_ms", int(stopSeconds * 1000));
  ASSERT_NO_FATAL_FAILURE(expectCancelled(stopSeconds, reports, status, 503));  // 503: retry (elsewhere)
  // The journal as it was; the next start serves the last acknowledged version, same mesh.
  EXPECT_EQ(data.sqlText("SELECT version FROM frames ORDER BY version"), frames_);
  RunningServer third(options(data));
  for (const RestoredScene& restored : third.server().restore()) {
    EXPECT_TRUE(restored.served);
    EXPECT_EQ(restored.problem, "");
  }
  TestClient client = third.client();
  client.set_read_timeout(120, 0);
  const auto back = client.Get(("/api/scenes/" + id_).c_str());  // on request, on PostgreSQL
  ASSERT_TRUE(back);
  ASSERT_EQ(back->status, 200) << back->body;
  EXPECT_EQ(bodyJson(back)["version"], version_);
  EXPECT_EQ(meshBin(client, id_), mesh_);
  EXPECT_EQ(bodyJson(client.Get("/api/health"))["status"], "ok");
}

}  // namespace
}  // namespace penumbra::server::test
