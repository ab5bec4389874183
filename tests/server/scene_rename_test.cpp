// PATCH /api/scenes/{id} (docs/API.md "rename"): a new name is answered with the summary, moves no
// version, is kept by frames applied after it (and while renames race with them) and by a restart
// on the same journal, on SQLite and on PostgreSQL; a bad name is a 422 at `name`, changing nothing.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "server_fixture.h"
#include "test_journal.h"

namespace penumbra::server::test {
namespace {

Reply patchName(TestClient& client, const std::string& id, const json& body) {
  return client.Patch(("/api/scenes/" + id).c_str(), body.dump(), "application/json");
}

// `frames` moves of cube_0 along x; returns the last acknowledged version.
uint64_t moves(TestClient& client, const std::string& id, int frames) {
  const json scene = bodyJson(client.Get(("/api/scenes/" + id).c_str()))["scene"];
  json transform;
  for (const json& object : scene["objects"])
    if (object["id"] == "cube_0") transform = object["transform"];
  uint64_t version = 0;
  for (int i = 0; i < frames; ++i) {
    transform["translate"][0] = transform["translate"][0].get<double>() + 0.01;
    const json frame = {{"edits", {{{"op", "move"}, {"id", "cube_0"}, {"transform", transform}}}}};
    const auto res = client.Post(("/api/scenes/" + id + "/edits").c_str(), frame.dump(), "application/json");
    EXPECT_TRUE(res && res->status == 200) << (res ? res->body : "no answer");
    version = bodyJson(res)["version"];
  }
  return version;
}

class RenameOnEachStore : public ::testing::TestWithParam<JournalBackend> {};

INSTANTIATE_TEST_SUITE_P(Stores, RenameOnEachStore,
                         ::testing::Values(JournalBackend::Sqlite, JournalBackend::Postgres), backendName);

TEST_P(RenameOnEachStore, ANameIsKeptByEditsAndARestart) {
  const TestJournal data(GetParam());
  std::string id;
  uint64_t version = 0;
  {
    RunningServer first(data.durable());
    auto client = first.client();
    id = first.addBundled("cubes15");
    const auto renamed = patchName(client, id, {{"name", "Kitchen · draft"}});
    ASSERT_TRUE(renamed && renamed->status == 200) << (renamed ? renamed->body : "no answer");
    EXPECT_EQ(bodyJson(renamed)["name"], "Kitchen · draft");
    EXPECT_EQ(bodyJson(renamed)["version"], 0);

    // Renames racing with frames: every frame applies, the last name set wins.
    std::atomic<bool> done{false};
    std::thread renamer([&] {
      auto other = first.client();
      for (int i = 0; !done; ++i) patchName(other, id, {{"name", "race " + std::to_string(i % 7)}});
    });
    version = moves(client, id, 8);
    done = true;
    renamer.join();
    EXPECT_EQ(version, 8u);
    ASSERT_EQ(patchName(client, id, {{"name", "Kitchen"}})->status, 200);

    for (const json& bad : {json::object(), json{{"name", 3}}, json{{"name", "  "}}, json{{"name", "a\nb"}},
                            json{{"name", std::string(201, 'x')}}, json::array()}) {
      const auto refused = patchName(client, id, bad);
      ASSERT_TRUE(refused);
      EXPECT_EQ(refused->status, 422) << bad.dump();
      EXPECT_EQ(bodyJson(refused)["error"]["code"], "invalid_name") << bad.dump();
      if (bad.is_object()) EXPECT_EQ(bodyJson(refused)["error"]["path"], "name") << bad.dump();
    }
    const json scene = bodyJson(client.Get(("/api/scenes/" + id).c_str()));
    EXPECT_EQ(scene["name"], "Kitchen");
    EXPECT_EQ(scene["version"], version);
    EXPECT_EQ(patchName(client, "nope", {{"name", "x"}})->status, 404);
  }
  RunningServer second(data.durable());
  second.server().restore();
  auto client = second.client();
  const json scene = bodyJson(client.Get(("/api/scenes/" + id).c_str()));
  EXPECT_EQ(scene["name"], "Kitchen");
  EXPECT_EQ(scene["version"], version);
}

}  // namespace
}  // namespace penumbra::server::test
