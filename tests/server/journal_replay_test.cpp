// A restart replays a scene's journaled frames through the engine alone and meshes once
// (SceneSession::replayJournaled, README "Durability"). The restored scene must serve what the
// server served before the restart: the whole binary mesh and the delta since every version,
// binary and JSON, byte for byte — with parts removed, parts come back, a relit scene (new
// radiance) and a full rebuild (a moved light) among the frames. Journaled part changes that do
// not read, and a journal from before they were recorded, replay frame by frame, as before.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <map>
#include <string>

#include "journal_answers.h"
#include "server_fixture.h"
#include "temp_data_dir.h"

namespace penumbra::server::test {
namespace {


// A frame of each kind the restore must replay (unit cubes standing on the floor, clear of the
// others); returns the last acknowledged version.
uint64_t play(TestClient& client, const std::string& id) {
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
      {{"edits", {{{"op", "remove"}, {"id", "cube_4"}}}}},  // its parts leave
      moveFrame("cube_1", -0.5, 0.5, 0.5, 30),
      {{"edits", {{{"op", "set_light"}, {"id", "light"}, {"radiance", {8, 9, 10}}}}}},
      {{"edits", {{{"op", "add"}, {"object", cube4}}}}},  // they come back
      moveFrame("cube_0", 0.2, 0.5, 0.3),
      {{"edits", {{{"op", "set_light"}, {"id", "light"}, {"polygon", light}}}}},  // a rebuild
      moveFrame("cube_1", -0.6, 0.5, 0.4, 45),
      moveFrame("cube_0", 0.15, 0.5, 0.35),
  };
  uint64_t version = 0;
  for (const json& frame : frames) {
    const auto res = postJson(client, edits, frame);
    EXPECT_TRUE(res && res->status == 200) << frame.dump() << " → " << (res ? res->body : "none");
    version = bodyJson(res)["version"];
  }
  return version;
}

// Restarts on `data`; checks the scene came back at `last`, replayed as `meshedOnce` says, and
// serves `before`.
void expectRestored(const TempDataDir& data, const std::string& id, uint64_t last,
                    bool meshedOnce, const Answers& before) {
  RunningServer server(data.durable());
  const std::vector<RestoredScene> restored = server.server().restore();
  ASSERT_EQ(restored.size(), 1u);
  EXPECT_TRUE(restored[0].problem.empty()) << restored[0].problem;
  EXPECT_EQ(restored[0].version, last);
  EXPECT_EQ(restored[0].frames, last);
  EXPECT_EQ(restored[0].meshedOnce, meshedOnce);
  auto client = server.client();
  const Answers after = served(client, id, last, false);
  ASSERT_EQ(after.size(), before.size());
  for (const auto& [query, body] : before)
    EXPECT_TRUE(after.at(query) == body) << query << " differs after the restart";
}

TEST(JournalReplay, MeshedOnceServesTheSameMeshAndDeltasAsBeforeTheRestart) {
  TempDataDir data;
  std::string id;
  uint64_t last = 0;
  Answers before;
  {
    RunningServer first(data.durable());
    id = first.addBundled("cubes15");
    auto client = first.client();
    last = play(client, id);
    ASSERT_EQ(last, 10u);
    before = served(client, id, last, false);
  }
  expectRestored(data, id, last, true, before);

  // Part changes that do not read: that scene replays frame by frame.
  sql(data, "UPDATE frames SET parts = 'not json' WHERE version = 4");
  expectRestored(data, id, last, false, before);

  // A journal from before the column: it is added (NULL), and the frames replay one by one.
  sql(data, "ALTER TABLE frames DROP COLUMN parts");
  expectRestored(data, id, last, false, before);
}

}  // namespace
}  // namespace penumbra::server::test
