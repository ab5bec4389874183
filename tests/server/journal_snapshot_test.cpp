// Issue 36, item 3: journal snapshots bound what a restart replays. Every snapshotEvery-th
// version the server rebuilds the scene's engine from the scene as the snapshot records it and
// journals that scene with its served parts; a restart starts from the newest snapshot that
// verifies and loads and replays only the frames after it. It must serve what the server served
// (the whole mesh and every `since` delta, byte for byte) from a snapshot, from an older one when
// the newest is damaged (said in health), and from no snapshot at all (the frames are never
// deleted, and say where the server built afresh).
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <map>
#include <random>
#include <string>

#include "server/scene_journal.h"
#include "server_fixture.h"
#include "temp_data_dir.h"
#include "tiny_scene.h"

namespace penumbra::server::test {
namespace {

using Answers = std::map<std::string, std::string>;  // query → body

ServerOptions snapshotting(const TempDataDir& data, uint64_t every) {
  ServerOptions options = data.durable();
  options.snapshotEvery = every;
  return options;
}

// Frames of each kind (as journal_replay_test): parts leave and come back, a relit scene, a
// rebuilding light edit; returns the last acknowledged version.
uint64_t playMixed(httplib::Client& client, const std::string& id) {
  const std::string edits = "/api/scenes/" + id + "/edits";
  const json scene = bodyJson(client.Get(("/api/scenes/" + id).c_str()))["scene"];
  json cube4;
  for (const json& object : scene["objects"])
    if (object["id"] == "cube_4") cube4 = object;
  json light = scene["lights"][0]["polygon"];
  for (json& corner : light) corner[0] = corner[0].get<double>() + 0.2;
  const std::vector<json> frames = {
      moveFrame("cube_0", 0.0, 0.5, 0.2),
      moveFrame("cube_0", 0.1, 0.5, 0.25),
      {{"edits", {{{"op", "remove"}, {"id", "cube_4"}}}}},
      moveFrame("cube_1", -0.5, 0.5, 0.5, 30),
      {{"edits", {{{"op", "set_light"}, {"id", "light"}, {"radiance", {8, 9, 10}}}}}},
      {{"edits", {{{"op", "add"}, {"object", cube4}}}}},
      moveFrame("cube_0", 0.2, 0.5, 0.3),
      moveFrame("cube_1", -0.6, 0.5, 0.4, 45),
      {{"edits", {{{"op", "set_light"}, {"id", "light"}, {"polygon", light}}}}},
      moveFrame("cube_0", 0.15, 0.5, 0.35),
      moveFrame("cube_1", -0.55, 0.5, 0.45, 40),
  };
  uint64_t version = 0;
  for (const json& frame : frames) {
    const auto res = postJson(client, edits, frame);
    EXPECT_TRUE(res && res->status == 200) << frame.dump() << " → " << (res ? res->body : "none");
    version = bodyJson(res)["version"];
  }
  return version;
}

Answers served(httplib::Client& client, const std::string& id, uint64_t last) {
  Answers out;
  std::vector<std::string> queries = {"?format=bin", ""};
  for (uint64_t since = 0; since <= last; ++since) {
    queries.push_back("?format=bin&since=" + std::to_string(since));
    queries.push_back("?since=" + std::to_string(since));
  }
  for (const std::string& query : queries) {
    const auto res = client.Get(("/api/scenes/" + id + "/mesh" + query).c_str());
    EXPECT_TRUE(res && res->status == 200) << query;
    out[query] = res ? res->body : "";
  }
  return out;
}

void sql(const TempDataDir& data, const std::string& statement) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open((data.str() + "/journal.sqlite3").c_str(), &db), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(db, statement.c_str(), nullptr, nullptr, nullptr), SQLITE_OK)
      << statement << ": " << sqlite3_errmsg(db);
  sqlite3_close(db);
}

std::string sqlText(const TempDataDir& data, const std::string& query) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open((data.str() + "/journal.sqlite3").c_str(), &db), SQLITE_OK);
  sqlite3_stmt* row = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(db, query.c_str(), -1, &row, nullptr), SQLITE_OK) << query;
  std::string text;
  if (sqlite3_step(row) == SQLITE_ROW && sqlite3_column_type(row, 0) != SQLITE_NULL)
    text = std::string(static_cast<const char*>(sqlite3_column_blob(row, 0)),
                       size_t(sqlite3_column_bytes(row, 0)));
  sqlite3_finalize(row);
  sqlite3_close(db);
  return text;
}

struct Restart {
  std::optional<uint64_t> snapshot;  // what the restore started from
  size_t frames = 0;                 // frames it replayed
  std::string snapshotProblem;
  json health;
};

// Restarts on `data` and checks the scene is back at `last` serving `before`, byte for byte.
Restart expectRestored(const TempDataDir& data, const std::string& id, uint64_t last,
                       const Answers& before, uint64_t every) {
  RunningServer server(snapshotting(data, every));
  const std::vector<RestoredScene> restored = server.server().restore();
  EXPECT_EQ(restored.size(), 1u);
  if (restored.size() != 1) return {};
  EXPECT_TRUE(restored[0].problem.empty()) << restored[0].problem;
  EXPECT_EQ(restored[0].version, last);
  auto client = server.client();
  const Answers after = served(client, id, last);
  EXPECT_EQ(after.size(), before.size());
  for (const auto& [query, body] : before)
    EXPECT_TRUE(after.at(query) == body) << query << " differs after the restart";
  return {restored[0].snapshot, restored[0].frames, restored[0].snapshotProblem,
          bodyJson(client.Get("/api/health"))};
}

TEST(JournalSnapshots, RestoreFromASnapshotOrAnOlderOneOrNoneServesTheSameBytes) {
  TempDataDir data;
  std::string id;
  uint64_t last = 0;
  Answers before;
  {
    RunningServer first(snapshotting(data, 4));
    id = first.addBundled("cubes15");
    auto client = first.client();
    last = playMixed(client, id);
    ASSERT_EQ(last, 11u);
    before = served(client, id, last);
  }
  // Snapshots at 4 and 8: the newest two kept; the frames after 4 were applied on a fresh build.
  EXPECT_EQ(sqlText(data, "SELECT group_concat(version) FROM snapshots"), "4,8");
  EXPECT_EQ(sqlText(data, "SELECT group_concat(base) FROM frames WHERE version > 3"),
            "0,4,4,4,4,8,9,9");  // 9, a moved light, rebuilt the engine itself
  Restart r = expectRestored(data, id, last, before, 4);
  EXPECT_EQ(r.snapshot, std::optional<uint64_t>(8));
  EXPECT_EQ(r.frames, 3u);
  EXPECT_TRUE(r.snapshotProblem.empty()) << r.snapshotProblem;
  EXPECT_EQ(r.health["status"], "ok");

  // The newest snapshot damaged: the one before, said in health.
  sql(data, "UPDATE snapshots SET source = 'x' || source WHERE version = 8");
  r = expectRestored(data, id, last, before, 4);
  EXPECT_EQ(r.snapshot, std::optional<uint64_t>(4));
  EXPECT_EQ(r.frames, 7u);
  EXPECT_NE(r.snapshotProblem.find("snapshot at version 8 fails its checksum"), std::string::npos)
      << r.snapshotProblem;
  EXPECT_EQ(r.health["status"], "degraded");
  ASSERT_EQ(r.health["journal"]["snapshot_problems"].size(), 1u);
  EXPECT_EQ(r.health["journal"]["snapshot_problems"][0]["id"], id);

  // The older one verifies but does not load: every frame, replayed on the same fresh builds.
  const std::string source = sqlText(data, "SELECT source FROM snapshots WHERE version = 4");
  const std::string parts = "not parts";
  sql(data, "UPDATE snapshots SET parts = '" + parts +
                "', crc = " + std::to_string(SceneJournal::snapshotChecksum(4, source, parts)) +
                " WHERE version = 4");
  r = expectRestored(data, id, last, before, 4);
  EXPECT_EQ(r.snapshot, std::nullopt);
  EXPECT_EQ(r.frames, last);
  EXPECT_NE(r.snapshotProblem.find("snapshot at version 4 does not load"), std::string::npos)
      << r.snapshotProblem;
  EXPECT_NE(r.snapshotProblem.find("replaying every frame"), std::string::npos);

  // No snapshot rows at all, frame by frame (part changes unreadable): the same bytes again.
  sql(data, "DELETE FROM snapshots");
  sql(data, "UPDATE frames SET parts = 'not json' WHERE version = 2");
  r = expectRestored(data, id, last, before, 0);
  EXPECT_EQ(r.snapshot, std::nullopt);
  EXPECT_EQ(r.frames, last);
  EXPECT_TRUE(r.snapshotProblem.empty());
  EXPECT_EQ(r.health["status"], "ok");
  // Restore only reads: no snapshot was written back, every frame is still there.
  EXPECT_EQ(sqlText(data, "SELECT COUNT(*) FROM snapshots"), "0");
  EXPECT_EQ(sqlText(data, "SELECT group_concat(version) FROM frames"), "1,2,3,4,5,6,7,8,9,10,11");
}

TEST(JournalSnapshots, ALongJournalReplaysOnlyTheTailAndKeepsEveryFrame) {
  TempDataDir data;
  constexpr int kFrames = 1050;
  std::string id;
  Answers before;
  {
    RunningServer first(snapshotting(data, 100));
    auto client = first.client();
    const auto res = postJson(client, "/api/scenes?name=tiny", tinyScene());
    ASSERT_EQ(res->status, 201) << res->body;
    id = bodyJson(res)["id"];
    std::mt19937 rng(36);
    std::uniform_real_distribution<double> where(-1.5, 1.5);
    for (int i = 1; i <= kFrames; ++i) {
      const auto edit = postJson(client, "/api/scenes/" + id + "/edits",
                                 moveFrame("box", where(rng), 0.5, where(rng)));
      ASSERT_TRUE(edit && edit->status == 200) << (edit ? edit->body : "no answer");
    }
    before = served(client, id, kFrames);
  }
  // Snapshots are dropped past the newest two; frames never.
  EXPECT_EQ(sqlText(data, "SELECT group_concat(version) FROM snapshots"), "900,1000");
  EXPECT_EQ(
      sqlText(data, "SELECT COUNT(*) || ' ' || MIN(version) || ' ' || MAX(version) FROM frames"),
      std::to_string(kFrames) + " 1 " + std::to_string(kFrames));
  Restart r = expectRestored(data, id, kFrames, before, 100);
  EXPECT_EQ(r.snapshot, std::optional<uint64_t>(1000));
  EXPECT_EQ(r.frames, 50u);
  // Every acknowledged version stays restorable from the frames alone.
  sql(data, "DELETE FROM snapshots");
  r = expectRestored(data, id, kFrames, before, 100);
  EXPECT_EQ(r.snapshot, std::nullopt);
  EXPECT_EQ(r.frames, size_t(kFrames));
}

}  // namespace
}  // namespace penumbra::server::test
