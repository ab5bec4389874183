// Every route while the PostgreSQL journal stops answering (its processes frozen by SIGSTOP, the
// connections left open): each request is answered within a bound of the connection's answer
// timeout, never 500. What needs the journal answers 503 journal_failed (an edit with "applied":
// false); what does not, answers as before. The freeze outlasts the leases, so the node drops its
// scenes and every scene request asks the journal (the takeover path); a scene journaled but
// served nowhere is asked for too. Nothing changes: once the database goes on, both scenes come
// back at their versions with the same meshes. (The edit route alone, with its timing:
// journal_postgres_test.cpp.)
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include "journal_answers.h"
#include "server_fixture.h"
#include "test_journal.h"
#include "tiny_scene.h"

namespace penumbra::server::test {
namespace {

constexpr int kAnswerSeconds = 1;  // the journal connection's connect_timeout

ServerOptions frozenNode(const TestJournal& data) {
  ServerOptions options = data.durable();
  options.journalDatabase += "&connect_timeout=" + std::to_string(kAnswerSeconds);
  options.nodeId = "frozen";
  options.restoreAtStart = false;
  return options;
}

struct RouteCall {
  std::string what;
  std::function<Reply(TestClient&)> call;
};

std::vector<RouteCall> everyRoute(const std::string& served, const std::string& journaled) {
  const std::string a = "/api/scenes/" + served, b = "/api/scenes/" + journaled;
  const json frame = moveFrame("box", 0.4, 0.5, -0.3);
  std::vector<RouteCall> calls = {
      {"GET /api/health", [](TestClient& c) { return c.Get("/api/health"); }},
      {"GET /api/scenes", [](TestClient& c) { return c.Get("/api/scenes"); }},
      {"POST /api/scenes",
       [](TestClient& c) { return postJson(c, "/api/scenes?name=new", tinyScene()); }},
  };
  for (const std::string& base : {a, b}) {
    calls.push_back({"GET " + base, [base](TestClient& c) { return c.Get(base.c_str()); }});
    calls.push_back({"GET mesh " + base, [base](TestClient& c) {
                       return c.Get((base + "/mesh?format=bin").c_str());
                     }});
    calls.push_back({"GET stats " + base,
                     [base](TestClient& c) { return c.Get((base + "/stats").c_str()); }});
    calls.push_back({"GET image " + base, [base](TestClient& c) {
                       return c.Get((base + "/image?width=16&height=12").c_str());
                     }});
    calls.push_back({"GET renders " + base,
                     [base](TestClient& c) { return c.Get((base + "/renders").c_str()); }});
    calls.push_back({"POST edits " + base, [base, frame](TestClient& c) {
                       return postJson(c, base + "/edits", frame);
                     }});
    calls.push_back({"PATCH " + base, [base](TestClient& c) {
                       return c.Patch(base.c_str(), R"({"name": "renamed"})", "application/json");
                     }});
    calls.push_back({"POST rebuild " + base, [base](TestClient& c) {
                       return c.Post((base + "/rebuild").c_str(), "", "application/json");
                     }});
  }
  return calls;
}

TEST(JournalUnreachable, EveryRouteOnAFrozenDatabaseAnswersWithoutA500AndChangesNothing) {
  const TestJournal data(JournalBackend::Postgres);
  PostgresCluster& cluster = PostgresCluster::shared();
  std::string served, journaled, servedMesh, journaledMesh;
  {  // a scene journaled and then given back: served nowhere
    RunningServer first(frozenNode(data));
    auto client = first.client();
    const auto created = postJson(client, "/api/scenes?name=kept", tinyScene());
    ASSERT_EQ(created->status, 201) << created->body;
    journaled = bodyJson(created)["id"];
    ASSERT_EQ(postJson(client, "/api/scenes/" + journaled + "/edits",
                       moveFrame("box", 1, 0.5, 1))->status, 200);
    journaledMesh = meshBin(client, journaled);
  }
  RunningServer running(frozenNode(data));
  auto client = running.client();
  const auto created = postJson(client, "/api/scenes?name=served", tinyScene());
  ASSERT_EQ(created->status, 201) << created->body;
  served = bodyJson(created)["id"];
  ASSERT_EQ(postJson(client, "/api/scenes/" + served + "/edits", moveFrame("box", -1, 0.5, 1))
                ->status,
            200);
  servedMesh = meshBin(client, served);

  cluster.pause();
  struct ResumeAtExit {
    PostgresCluster& cluster;
    ~ResumeAtExit() { cluster.resume(); }
  } resumeAtExit{cluster};
  // A journal read, a reconnection and a lease query, each bounded by the answer timeout.
  const double kBound = 4 * kAnswerSeconds + 2 * kTimingSlowdown;
  {  // the lease runs out during the first calls: the later ones take the takeover path
    for (const RouteCall& route : everyRoute(served, journaled)) {
      const auto start = std::chrono::steady_clock::now();
      const Reply reply = route.call(client);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      SCOPED_TRACE(route.what);
      ASSERT_TRUE(reply) << "no answer after " << seconds << " s";
      EXPECT_LT(seconds, kBound) << "it waited on the frozen database";
      EXPECT_NE(reply->status, 500) << reply->body;
      if (reply->status >= 500) {
        EXPECT_EQ(reply->status, 503) << reply->body;
        EXPECT_EQ(bodyJson(reply)["error"]["code"], "journal_failed") << reply->body;
      }
      if (route.what.rfind("POST edits", 0) == 0 || route.what.rfind("PATCH", 0) == 0 ||
          route.what.rfind("POST /api/scenes", 0) == 0) {
        EXPECT_GE(reply->status, 500) << "a write succeeded without its journal: " << reply->body;
      }
      if (route.what.rfind("POST edits", 0) == 0 && reply->status == 503) {
        EXPECT_EQ(bodyJson(reply)["error"]["applied"], false) << reply->body;
      }
    }
  }

  cluster.resume();
  for (const auto& [id, mesh] : {std::pair{served, servedMesh}, {journaled, journaledMesh}}) {
    const json scene = bodyJson(client.Get(("/api/scenes/" + id).c_str()));
    EXPECT_EQ(scene["version"], 1) << id;
    EXPECT_NE(scene["name"], "renamed") << id;
    EXPECT_TRUE(meshBin(client, id) == mesh) << id << ": a refused request changed the mesh";
  }
  EXPECT_EQ(data.sqlText("SELECT count(*) FROM scenes"), "2");
}

}  // namespace
}  // namespace penumbra::server::test
