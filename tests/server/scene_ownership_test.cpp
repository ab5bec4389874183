// One owner per scene among nodes sharing a PostgreSQL journal (docs/SERVER.md "Many nodes"), on
// the binary's private test cluster: a journal write under a lease another node took over is
// refused with nothing written; two servers on one database serve each scene from one of them,
// the other answering 503 + Retry-After until the owner hands it over (asked, or stopping), and
// the new owner serves the same version with a byte-identical mesh. (A node frozen past its lease
// and fenced: tests/server/scene_fencing.py, with real processes.)
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <random>
#include <string>
#include <thread>

#include "journal_answers.h"
#include "server/scene_journal.h"
#include "server/scene_leases.h"
#include "server_fixture.h"
#include "test_journal.h"
#include "tiny_scene.h"

namespace penumbra::server::test {
namespace {

ServerOptions node(const TestJournal& data, const std::string& name, double leaseSeconds) {
  ServerOptions options = RunningServer::loopback();
  options.dataDir = data.dir().str() + "/" + name;
  options.journalDatabase = data.database();
  options.nodeId = name;
  options.leaseSeconds = leaseSeconds;
  options.restoreAtStart = false;
  return options;
}

// Asks `client` for scene `id` until it serves it (503 owned_elsewhere meanwhile); the answer.
Reply waitServed(TestClient& client, const std::string& id, double seconds) {
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  for (;;) {
    auto answer = client.Get(("/api/scenes/" + id).c_str());
    if (!answer || answer->status != 503 || std::chrono::steady_clock::now() > deadline)
      return answer;
    EXPECT_EQ(answer->get_header_value("Retry-After"), "1");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

TEST(SceneOwnership, AWriteUnderALeaseTakenOverIsRefusedAndWritesNothing) {
  const TestJournal data(JournalBackend::Postgres);
  SceneJournal journal(data.dir().str(), data.database());
  SceneLeases first(data.database(), "first", 30), second(data.database(), "second", 30);
  SceneLeases::Holder holder;
  const auto token = first.acquire("a", holder);
  ASSERT_TRUE(token);
  const int64_t key = journal.addScene("a", "a", "{}", 0, *token);
  journal.addFrame(key, 1, "one", "", 0);
  const std::string upload = "volumes/a-0000000000000001.nrrd";
  journal.addVolume(key, upload, "bytes");
  EXPECT_FALSE(second.acquire("a", holder));  // held, and not expired
  EXPECT_EQ(holder.node, "first");
  EXPECT_GT(holder.secondsLeft, 20);
  EXPECT_EQ(data.sqlText("SELECT wanted_by FROM scene_leases"), "second");

  data.sql("UPDATE scene_leases SET expires = now() - interval '1 second'");  // first stalled
  const auto taken = second.acquire("a", holder);
  ASSERT_TRUE(taken);
  EXPECT_GT(*taken, *token);
  EXPECT_THROW(journal.addFrame(key, 2, "stale", "", 0), LeaseLost);
  EXPECT_THROW(journal.addSnapshot(key, 1, "{}", ""), LeaseLost);
  EXPECT_THROW(journal.removeScene(key), LeaseLost);
  EXPECT_THROW(journal.addVolume(key, "volumes/a-0000000000000002.nrrd", "stale"), LeaseLost);
  EXPECT_THROW(journal.removeVolume(key, upload), LeaseLost);
  EXPECT_EQ(data.sqlText("SELECT name FROM volumes"), upload);
  EXPECT_EQ(data.sqlText("SELECT count(*) FROM volume_chunks"), "1");
  EXPECT_EQ(data.sqlText("SELECT frame FROM frames ORDER BY version"), "one");
  EXPECT_EQ(data.sqlText("SELECT count(*) FROM snapshots"), "0");
  EXPECT_TRUE(first.renew().held.empty());  // the first node learns it lost the lease

  SceneJournal newOwner(data.dir().str() + "-2", data.database());
  const auto stored = newOwner.loadScene("a", *taken);
  ASSERT_TRUE(stored);
  ASSERT_EQ(stored->frames.size(), 1u);
  newOwner.addFrame(key, 2, "two", "", 0);
  EXPECT_EQ(data.sqlText("SELECT frame FROM frames ORDER BY version"), "one,two");
  EXPECT_EQ(second.renew().held.at("a"), *taken);
}

TEST(SceneOwnership, TwoNodesServeASceneFromOneOwnerThatHandsItOverWhenAsked) {
  const TestJournal data(JournalBackend::Postgres);
  std::mt19937 rng(39);
  std::uniform_real_distribution<double> where(-1.5, 1.5);
  RunningServer a(node(data, "a", 1.5)), b(node(data, "b", 1.5));
  auto clientA = a.client(), clientB = b.client();
  const auto created = postJson(clientA, "/api/scenes?name=tiny", tinyScene());
  ASSERT_EQ(created->status, 201) << created->body;
  const std::string id = bodyJson(created)["id"];
  for (int i = 0; i < 3; ++i)
    ASSERT_EQ(postJson(clientA, "/api/scenes/" + id + "/edits",
                       moveFrame("box", where(rng), 0.5, where(rng)))
                  ->status,
              200);
  const std::string mesh = meshBin(clientA, id);

  const auto refused = clientB.Get(("/api/scenes/" + id).c_str());
  ASSERT_EQ(refused->status, 503) << refused->body;
  EXPECT_EQ(bodyJson(refused)["error"]["code"], "owned_elsewhere");
  EXPECT_EQ(refused->get_header_value("Retry-After"), "1");
  // Asked, the owner hands it over at its next renewal (a third of the lease).
  const auto served = waitServed(clientB, id, 5);
  ASSERT_EQ(served->status, 200) << served->body;
  EXPECT_EQ(bodyJson(served)["version"], 3);
  EXPECT_TRUE(meshBin(clientB, id) == mesh) << "the new owner serves another mesh";
  EXPECT_EQ(a.server().servesScene(id), false);
  EXPECT_EQ(bodyJson(clientB.Get("/api/health"))["journal"]["node"], "b");

  const auto edit = postJson(clientB, "/api/scenes/" + id + "/edits",
                             moveFrame("box", where(rng), 0.5, where(rng)));
  ASSERT_EQ(edit->status, 200) << edit->body;
  EXPECT_EQ(bodyJson(edit)["version"], 4);
  EXPECT_EQ(data.sqlText("SELECT version FROM frames ORDER BY version"), "1,2,3,4");

  // A second scene of the same name on the other node gets its own id.
  const auto again = postJson(clientA, "/api/scenes?name=tiny", tinyScene());
  ASSERT_EQ(again->status, 201) << again->body;
  EXPECT_NE(bodyJson(again)["id"], id);
}

TEST(SceneOwnership, AStoppingNodeGivesItsLeasesBackAndAnotherServesItsScenesAtOnce) {
  const TestJournal data(JournalBackend::Postgres);
  std::string id, mesh;
  std::optional<RunningServer> a(std::in_place, node(data, "a", 30));
  RunningServer b(node(data, "b", 30));
  {
    auto client = a->client();
    const auto created = postJson(client, "/api/scenes?name=tiny", tinyScene());
    ASSERT_EQ(created->status, 201) << created->body;
    id = bodyJson(created)["id"];
    ASSERT_EQ(postJson(client, "/api/scenes/" + id + "/edits", moveFrame("box", 1, 0.5, 1))
                  ->status,
              200);
    mesh = meshBin(client, id);
  }
  a.reset();  // SIGTERM's path: the server stops and hands its leases back
  auto client = b.client();
  const auto served = client.Get(("/api/scenes/" + id).c_str());  // not 30 s later
  ASSERT_EQ(served->status, 200) << served->body;
  EXPECT_EQ(bodyJson(served)["version"], 1);
  EXPECT_TRUE(meshBin(client, id) == mesh);
  EXPECT_EQ(client.Get("/api/scenes/nothing")->status, 404);
}


// Memory follows use: a scene nobody asked for within --idle-release (and with no event stream
// open) is dropped and its lease given back; asked again, it comes back at its version. A scene
// handed over ends its event streams, so clients reconnect to the new owner.
TEST(SceneOwnership, AnIdleSceneIsGivenBackAndAHandedOverScenesStreamsEnd) {
  const TestJournal data(JournalBackend::Postgres);
  ServerOptions idle = node(data, "a", 0.6);
  idle.idleReleaseSeconds = 1;
  RunningServer a(idle), b(node(data, "b", 0.6));
  auto client = a.client();
  const auto created = postJson(client, "/api/scenes?name=tiny", tinyScene());
  ASSERT_EQ(created->status, 201) << created->body;
  const std::string id = bodyJson(created)["id"];
  ASSERT_EQ(postJson(client, "/api/scenes/" + id + "/edits", moveFrame("box", 1, 0.5, 1))->status,
            200);
  const std::string mesh = meshBin(client, id);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (a.server().servesScene(id) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_FALSE(a.server().servesScene(id)) << "the idle scene is still served";
  EXPECT_EQ(data.sqlText("SELECT expires <= now() FROM scene_leases"), "t");
  const auto back = client.Get(("/api/scenes/" + id).c_str());
  ASSERT_EQ(back->status, 200) << back->body;
  EXPECT_EQ(bodyJson(back)["version"], 1);
  EXPECT_TRUE(meshBin(client, id) == mesh);

  std::atomic<bool> streamEnded{false};
  std::thread stream([&] {
    auto streamClient = a.client();
    streamClient.Get(("/api/scenes/" + id + "/events").c_str(),
                     [](const char*, size_t) { return true; });
    streamEnded = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // open, and not idle
  EXPECT_TRUE(a.server().servesScene(id)) << "a scene with an open event stream was given back";
  auto clientB = b.client();
  const auto served = waitServed(clientB, id, 5);
  EXPECT_EQ(served->status, 200) << served->body;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!streamEnded && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_TRUE(streamEnded) << "the handed-over scene's event stream is still open";
  if (!streamEnded) a.server().stop();  // ends it, so the thread can be joined
  stream.join();
  EXPECT_FALSE(a.server().servesScene(id));
}

}  // namespace
}  // namespace penumbra::server::test
