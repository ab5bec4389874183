// Issue 36, item 3: journal snapshots bound what a restart replays. Every snapshotEvery-th
// version the server rebuilds the scene's engine from the scene as the snapshot records it and
// journals that scene with its served parts; a restart starts from the newest snapshot that
// verifies and loads and replays only the frames after it. It must serve what the server served
// (the whole mesh and every `since` delta, byte for byte) from a snapshot, from an older one when
// the newest is damaged (said in health), and from no snapshot at all (the frames are never
// deleted, and say where the server built afresh).
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <string>

#include "server/scene_journal.h"
#include "journal_answers.h"
#include "server_fixture.h"
#include "test_journal.h"
#include "tiny_scene.h"

namespace penumbra::server::test {
namespace {


ServerOptions snapshotting(const TestJournal& data, uint64_t every) {
  ServerOptions options = data.durable();
  options.snapshotEvery = every;
  return options;
}

// Frames of each kind (as journal_replay_test): parts leave and come back, a relit scene, a
// rebuilding light edit; returns the last acknowledged version.
uint64_t playMixed(TestClient& client, const std::string& id) {
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

// Seeded frames over the cubes: moves with a turn, removals, objects added back (refused frames,
// such as moves out of the edit volume, are skipped); returns the last acknowledged version.
// Unlike plain drags, these give a fresh build meshes that differ from the incremental ones in
// the last bits: a restart that did not build afresh where the server did, or did not keep the
// served bytes of the parts no later frame changed, would fail the byte comparisons.
uint64_t playRandom(TestClient& client, const std::string& id, int frames, uint32_t seed) {
  const std::string edits = "/api/scenes/" + id + "/edits";
  const json scene = bodyJson(client.Get(("/api/scenes/" + id).c_str()))["scene"];
  std::vector<json> cubes, removed;
  for (const json& object : scene["objects"])
    if (object["id"].get<std::string>().rfind("cube", 0) == 0) cubes.push_back(object);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  uint64_t version = bodyJson(client.Get(("/api/scenes/" + id).c_str()))["version"];
  for (int i = 0; i < frames; ++i) {
    const double kind = unit(rng);
    json frame;
    size_t index = 0;
    if (kind < 0.1 && cubes.size() > 3) {
      index = size_t(unit(rng) * double(cubes.size())) % cubes.size();
      frame = {{"edits", {{{"op", "remove"}, {"id", cubes[index]["id"]}}}}};
    } else if (kind < 0.2 && !removed.empty()) {
      frame = {{"edits", {{{"op", "add"}, {"object", removed.back()}}}}};
    } else {
      index = size_t(unit(rng) * double(cubes.size())) % cubes.size();
      json transform = cubes[index].value("transform", json{{"translate", {0, 0, 0}}});
      transform["translate"][0] = transform["translate"][0].get<double>() + 0.6 * unit(rng) - 0.3;
      transform["translate"][2] = transform["translate"][2].get<double>() + 0.6 * unit(rng) - 0.3;
      transform["rotate_deg"] = {0, 90 * unit(rng), 0};
      frame = {{"edits", {{{"op", "move"}, {"id", cubes[index]["id"]}, {"transform", transform}}}}};
    }
    const auto res = postJson(client, edits, frame);
    if (!res || res->status != 200) continue;  // refused: nothing changed
    version = bodyJson(res)["version"];
    const std::string op = frame["edits"][0]["op"];
    if (op == "remove") {
      removed.push_back(cubes[index]);
      cubes.erase(cubes.begin() + long(index));
    } else if (op == "add") {
      cubes.push_back(removed.back());
      removed.pop_back();
    } else {
      cubes[index]["transform"] = frame["edits"][0]["transform"];
    }
  }
  return version;
}

struct Restart {
  std::optional<uint64_t> snapshot;  // what the restore started from
  size_t frames = 0;                 // frames it replayed
  std::string snapshotProblem;
  json health;
};

// Restarts on `data` and checks the scene is back at `last` serving `before`, byte for byte.
Restart expectRestored(const TestJournal& data, const std::string& id, uint64_t last,
                       const Answers& before, uint64_t every) {
  RunningServer server(snapshotting(data, every));
  const std::vector<RestoredScene> restored = server.server().restore();
  EXPECT_EQ(restored.size(), 1u);
  if (restored.size() != 1) return {};
  EXPECT_TRUE(restored[0].problem.empty()) << restored[0].problem;
  EXPECT_EQ(restored[0].version, last);
  auto client = server.client();
  const Answers after = served(client, id, last, true);
  EXPECT_EQ(after.size(), before.size());
  for (const auto& [query, body] : before)
    EXPECT_TRUE(after.at(query) == body) << query << " differs after the restart";
  return {restored[0].snapshot, restored[0].frames, restored[0].snapshotProblem,
          bodyJson(client.Get("/api/health"))};
}

class JournalSnapshots : public ::testing::TestWithParam<JournalBackend> {};

INSTANTIATE_TEST_SUITE_P(Stores, JournalSnapshots,
                         ::testing::Values(JournalBackend::Sqlite, JournalBackend::Postgres),
                         backendName);

TEST_P(JournalSnapshots, RestoreFromASnapshotOrAnOlderOneOrNoneServesTheSameBytes) {
  const TestJournal data(GetParam());
  std::string id;
  uint64_t last = 0;
  Answers before;
  {
    RunningServer first(snapshotting(data, 5));
    id = first.addBundled("cubes15");
    auto client = first.client();
    ASSERT_EQ(playMixed(client, id), 11u);
    last = playRandom(client, id, 32, 36);
    ASSERT_GT(last, 25u);
    before = served(client, id, last, true);
  }
  const uint64_t newest = last / 5 * 5, older = newest - 5;
  // The newest two snapshots kept; each frame names the build it was applied on: the snapshots
  // at 5 and 10, and 9 (a moved light) rebuilt the engine itself.
  EXPECT_EQ(data.sqlText("SELECT version FROM snapshots ORDER BY version"),
            std::to_string(older) + "," + std::to_string(newest));
  EXPECT_EQ(data.sqlText("SELECT base FROM frames WHERE version BETWEEN 4 AND 11 ORDER BY version"),
            "0,0,5,5,5,5,9,10");
  Restart r = expectRestored(data, id, last, before, 5);
  EXPECT_EQ(r.snapshot, std::optional<uint64_t>(newest));
  EXPECT_EQ(r.frames, last - newest);
  EXPECT_TRUE(r.snapshotProblem.empty()) << r.snapshotProblem;
  EXPECT_EQ(r.health["status"], "ok");

  // The newest snapshot damaged: the one before, said in health.
  data.sql("UPDATE snapshots SET source = 'x' || source WHERE version = " + std::to_string(newest));
  r = expectRestored(data, id, last, before, 5);
  EXPECT_EQ(r.snapshot, std::optional<uint64_t>(older));
  EXPECT_EQ(r.frames, last - older);
  EXPECT_NE(r.snapshotProblem.find("snapshot at version " + std::to_string(newest) +
                                   " fails its checksum"),
            std::string::npos)
      << r.snapshotProblem;
  EXPECT_EQ(r.health["status"], "degraded");
  ASSERT_EQ(r.health["journal"]["snapshot_problems"].size(), 1u);
  EXPECT_EQ(r.health["journal"]["snapshot_problems"][0]["id"], id);

  // The older one verifies but does not load: every frame, replayed on the same fresh builds.
  const std::string where = " WHERE version = " + std::to_string(older);
  const std::string source = data.sqlText("SELECT source FROM snapshots" + where);
  const std::string parts = "not parts";
  data.sql("UPDATE snapshots SET parts = '" + parts + "', crc = " +
                std::to_string(SceneJournal::snapshotChecksum(older, source, parts)) + where);
  r = expectRestored(data, id, last, before, 5);
  EXPECT_EQ(r.snapshot, std::nullopt);
  EXPECT_EQ(r.frames, last);
  EXPECT_NE(
      r.snapshotProblem.find("snapshot at version " + std::to_string(older) + " does not load"),
      std::string::npos)
      << r.snapshotProblem;
  EXPECT_NE(r.snapshotProblem.find("replaying every frame"), std::string::npos);

  // No snapshot rows at all, frame by frame (part changes unreadable): the same bytes again.
  data.sql("DELETE FROM snapshots");
  data.sql("UPDATE frames SET parts = 'not json' WHERE version = 2");
  r = expectRestored(data, id, last, before, 0);
  EXPECT_EQ(r.snapshot, std::nullopt);
  EXPECT_EQ(r.frames, last);
  EXPECT_TRUE(r.snapshotProblem.empty());
  EXPECT_EQ(r.health["status"], "ok");
  // Restore only reads: no snapshot was written back, every frame is still there.
  EXPECT_EQ(data.sqlText("SELECT COUNT(*) FROM snapshots"), "0");
  EXPECT_EQ(data.sqlText("SELECT COUNT(*) || ' ' || MAX(version) FROM frames"),
            std::to_string(last) + " " + std::to_string(last));
}

TEST_P(JournalSnapshots, ALongJournalReplaysOnlyTheTailAndKeepsEveryFrame) {
  const TestJournal data(GetParam());
  // Snapshots every 8: 8 … 80, a tail of 6 (was 430 frames every 40: the same checks, at 22 s in
  // Release and minutes under the sanitizers).
  constexpr int kFrames = 86, kEvery = 8;
  std::string id;
  Answers before;
  {
    RunningServer first(snapshotting(data, kEvery));
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
    before = served(client, id, kFrames, true);
  }
  // Snapshots are dropped past the newest two; frames never.
  EXPECT_EQ(data.sqlText("SELECT version FROM snapshots ORDER BY version"), "72,80");
  EXPECT_EQ(
      data.sqlText("SELECT COUNT(*) || ' ' || MIN(version) || ' ' || MAX(version) FROM frames"),
      std::to_string(kFrames) + " 1 " + std::to_string(kFrames));
  Restart r = expectRestored(data, id, kFrames, before, kEvery);
  EXPECT_EQ(r.snapshot, std::optional<uint64_t>(80));
  EXPECT_EQ(r.frames, 6u);
  // Every acknowledged version stays restorable from the frames alone.
  data.sql("DELETE FROM snapshots");
  r = expectRestored(data, id, kFrames, before, kEvery);
  EXPECT_EQ(r.snapshot, std::nullopt);
  EXPECT_EQ(r.frames, size_t(kFrames));
}

}  // namespace
}  // namespace penumbra::server::test
