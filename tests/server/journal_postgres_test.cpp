// The journal on PostgreSQL when the database goes away: with its server stopped while a
// Penumbra server serves, edits and new scenes answer 503 journal_failed (nothing applied) and
// /api/health says durable: false; once it is back the same server journals again, and a restart
// serves every acknowledged version byte for byte; a commit whose answer was lost does not block
// the scene; a database frozen without closing the connection makes edits 503 within the answer
// timeout, not hang. (What holds for both stores is in
// journal_test.cpp, journal_snapshot_test.cpp and scene_journal_test.cpp.)
#include <gtest/gtest.h>

#include <chrono>
#include <random>
#include <string>
#include <vector>

#include "journal_answers.h"
#include "server/scene_journal.h"
#include "server_fixture.h"
#include "test_journal.h"
#include "tiny_scene.h"

namespace penumbra::server::test {
namespace {

Reply moveBox(TestClient& client, const std::string& id, std::mt19937& rng) {
  std::uniform_real_distribution<double> where(-1.5, 1.5);
  return postJson(client, "/api/scenes/" + id + "/edits",
                  moveFrame("box", where(rng), 0.5, where(rng)));
}

TEST(JournalPostgres, TheDatabaseStoppedWhileServingMakesEdits503AndLosesNothing) {
  const TestJournal data(JournalBackend::Postgres);
  PostgresCluster& cluster = PostgresCluster::shared();
  std::mt19937 rng(39);
  std::string id, mesh;
  uint64_t version = 0;
  {
    RunningServer running(data.durable());
    auto client = running.client();
    const auto created = postJson(client, "/api/scenes?name=tiny", tinyScene());
    ASSERT_EQ(created->status, 201) << created->body;
    id = bodyJson(created)["id"];
    for (int i = 0; i < 3; ++i) ASSERT_EQ(moveBox(client, id, rng)->status, 200);
    mesh = meshBin(client, id);
    EXPECT_EQ(bodyJson(client.Get("/api/health"))["durable"], true);

    cluster.stop();
    for (int i = 0; i < 2; ++i) {  // the lost connection, then one that cannot be opened
      const auto edit = moveBox(client, id, rng);
      ASSERT_TRUE(edit);
      EXPECT_EQ(edit->status, 503) << edit->body;
      EXPECT_EQ(bodyJson(edit)["error"]["code"], "journal_failed");
      EXPECT_EQ(bodyJson(edit)["error"]["applied"], false);
    }
    const auto scene = postJson(client, "/api/scenes?name=more", tinyScene());
    EXPECT_EQ(scene->status, 503) << scene->body;
    const json health = bodyJson(client.Get("/api/health"));
    EXPECT_EQ(health["durable"], false);
    EXPECT_EQ(health["status"], "degraded");
    EXPECT_NE(health["journal"]["durability"].get<std::string>().find("cannot be reached"),
              std::string::npos)
        << health.dump();
    EXPECT_EQ(bodyJson(client.Get(("/api/scenes/" + id).c_str()))["version"], 3);
    EXPECT_TRUE(meshBin(client, id) == mesh) << "a refused edit changed the served mesh";

    cluster.start();  // the server connects again by itself
    EXPECT_EQ(bodyJson(client.Get("/api/health"))["durable"], true);
    for (int i = 0; i < 2; ++i) {
      const auto edit = moveBox(client, id, rng);
      ASSERT_TRUE(edit && edit->status == 200) << (edit ? edit->body : "no answer");
      version = bodyJson(edit)["version"];
    }
    EXPECT_EQ(version, 5u);
    mesh = meshBin(client, id);
  }
  RunningServer again(data.durable());
  const auto restored = again.server().restore();
  ASSERT_EQ(restored.size(), 1u);
  EXPECT_TRUE(restored[0].problem.empty()) << restored[0].problem;
  EXPECT_EQ(restored[0].version, version);
  auto client = again.client();
  EXPECT_TRUE(meshBin(client, id) == mesh);
  EXPECT_EQ(data.sqlText("SELECT version FROM frames ORDER BY version"), "1,2,3,4,5");
}

// A database that stops answering without closing the connection (every process of it frozen
// by SIGSTOP): an edit answers 503 journal_failed once the connection's answer timeout
// (connect_timeout, 2 s here) has passed, instead of hanging; so does the next, whose
// reconnection times out the same way; nothing is applied. The freeze outlasts the scene's lease
// (the node stops serving it: it cannot renew), so once the database goes on, the same server
// takes the scene back on the next request, at the last acknowledged version, and journals again.
TEST(JournalPostgres, AFrozenDatabaseMakesEdits503WithinTheTimeoutAndTheServerRecovers) {
  const TestJournal data(JournalBackend::Postgres);
  PostgresCluster& cluster = PostgresCluster::shared();
  ServerOptions options = data.durable();
  options.journalDatabase += "&connect_timeout=2";
  constexpr double kBound = 2 + 1.5;  // the timeout, and time for the request itself
  std::mt19937 rng(41);
  RunningServer running(options);
  auto client = running.client();
  const auto created = postJson(client, "/api/scenes?name=tiny", tinyScene());
  ASSERT_EQ(created->status, 201) << created->body;
  const std::string id = bodyJson(created)["id"];
  for (int i = 0; i < 2; ++i) ASSERT_EQ(moveBox(client, id, rng)->status, 200);
  const std::string mesh = meshBin(client, id);

  cluster.pause();
  struct ResumeAtExit {
    PostgresCluster& cluster;
    ~ResumeAtExit() { cluster.resume(); }
  } resumeAtExit{cluster};
  for (int i = 0; i < 2; ++i) {  // the silent connection, then a reconnection that times out
    const auto start = std::chrono::steady_clock::now();
    const auto edit = moveBox(client, id, rng);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_TRUE(edit) << "no answer after " << seconds << " s";
    EXPECT_EQ(edit->status, 503) << edit->body;
    EXPECT_EQ(bodyJson(edit)["error"]["code"], "journal_failed");
    EXPECT_EQ(bodyJson(edit)["error"]["applied"], false);
    EXPECT_LT(seconds, kBound) << "edit " << i << " waited on the frozen database";
  }
  cluster.resume();
  EXPECT_EQ(bodyJson(client.Get(("/api/scenes/" + id).c_str()))["version"], 2);
  EXPECT_TRUE(meshBin(client, id) == mesh) << "a refused edit changed the served mesh";
  const auto edit = moveBox(client, id, rng);
  ASSERT_TRUE(edit && edit->status == 200) << (edit ? edit->body : "no answer");
  EXPECT_EQ(bodyJson(edit)["version"], 3);
  EXPECT_EQ(data.sqlText("SELECT version FROM frames ORDER BY version"), "1,2,3");
}

// A commit whose answer the lost connection swallowed leaves a row at a version never
// acknowledged: the next frame at that version takes its place instead of failing every retry,
// and an acknowledged row is never overwritten (the version-gap rule).
TEST(JournalPostgres, AFrameWhoseCommitWasNeverAcknowledgedIsReplacedByTheNextOne) {
  const TestJournal data(JournalBackend::Postgres);
  SceneJournal journal(data.dir().str(), data.database());
  const int64_t key = journal.addScene("a", "a", "{}", 0);
  journal.addFrame(key, 1, "one", "", 0);
  data.sql("INSERT INTO frames (scene, version, frame) VALUES (" + std::to_string(key) +
           ", 2, 'lost answer')");
  EXPECT_THROW(journal.addFrame(key, 1, "one again", "", 0), std::runtime_error);
  journal.addFrame(key, 2, "two", "", 0);
  EXPECT_EQ(data.sqlText("SELECT frame FROM frames ORDER BY version"), "one,two");
  const auto scenes = journal.load();
  ASSERT_EQ(scenes.size(), 1u);
  ASSERT_EQ(scenes[0].frames.size(), 2u);
  EXPECT_TRUE(scenes[0].frames[1].intact);
}

}  // namespace
}  // namespace penumbra::server::test
