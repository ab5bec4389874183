// Issue 36, item 2: the journal never deletes what it acknowledged. Restore is read-only: a frame
// that fails its checksum or no longer applies stalls the scene at the version before (served,
// edits 409, said in health and the scene list) and every frame stays in the journal; uploads are
// kept relative to the data directory, so a moved directory restores every version; a directory
// removed while serving turns edits into 503 and health into durable: false; one server per
// data directory. Restarts serve byte-identical meshes for the versions they serve.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/resource.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <map>
#include <random>

#include "server/data_directory.h"
#include "journal_answers.h"
#include "server_fixture.h"
#include "temp_data_dir.h"
#include "tiny_scene.h"

namespace penumbra::server::test {
namespace {

namespace fs = std::filesystem;

json sceneJson(TestClient& client, const std::string& id) {
  return bodyJson(client.Get(("/api/scenes/" + id).c_str()));
}

// Seeded moves of the box; the mesh served at each version (index = version).
std::vector<std::string> dragBox(TestClient& client, const std::string& id, int frames,
                                 uint32_t seed, std::vector<std::string> meshes = {}) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> where(-1.5, 1.5);
  if (meshes.empty()) meshes.push_back(meshBin(client, id));
  for (int i = 0; i < frames; ++i) {
    const auto res = postJson(client, "/api/scenes/" + id + "/edits",
                              moveFrame("box", where(rng), 0.5, where(rng)));
    EXPECT_TRUE(res && res->status == 200) << (res ? res->body : "no answer");
    EXPECT_EQ(bodyJson(res)["version"], meshes.size());
    meshes.push_back(meshBin(client, id));
  }
  return meshes;
}

std::string addTiny(TestClient& client) {
  const auto res = postJson(client, "/api/scenes?name=tiny", tinyScene());
  EXPECT_EQ(res->status, 201) << res->body;
  return bodyJson(res)["id"];
}

// The journal's frames (version → frame text) of every scene, read straight from the file.
std::map<int64_t, std::string> journaledFrames(const std::string& dir) {
  std::map<int64_t, std::string> frames;
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open((dir + "/journal.sqlite3").c_str(), &db), SQLITE_OK);
  sqlite3_stmt* rows = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(db, "SELECT version, frame FROM frames ORDER BY version", -1, &rows,
                               nullptr),
            SQLITE_OK);
  while (sqlite3_step(rows) == SQLITE_ROW)
    frames[sqlite3_column_int64(rows, 0)] =
        std::string(static_cast<const char*>(sqlite3_column_blob(rows, 1)),
                    size_t(sqlite3_column_bytes(rows, 1)));
  sqlite3_finalize(rows);
  sqlite3_close(db);
  return frames;
}

void execSql(const std::string& dir, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open((dir + "/journal.sqlite3").c_str(), &db), SQLITE_OK);
  char* error = nullptr;
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error), SQLITE_OK)
      << (error ? error : "");
  sqlite3_free(error);
  sqlite3_close(db);
}

std::string smokeBytes() {
  return protocol::readTextFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/volumes/smoke64.nrrd",
                                size_t(1) << 24);
}

TEST(JournalFaults, AMovedDataDirectoryRestoresEveryAcknowledgedVersionWithItsUploads) {
  TempDataDir data, moved;
  std::vector<std::string> meshes;
  std::string id;
  {
    RunningServer running(data.durable());
    auto client = running.client();
    id = addTiny(client);
    meshes = dragBox(client, id, 2, 1);
    const auto upload =
        client.Post(("/api/scenes/" + id + "/volumes?name=smoke.nrrd&translate=2,1,2").c_str(),
                    smokeBytes(), "application/octet-stream");
    ASSERT_EQ(upload->status, 201) << upload->body;
    meshes.push_back(meshBin(client, id));
    meshes = dragBox(client, id, 4, 2, meshes);
  }
  const auto frames = journaledFrames(data.str());
  ASSERT_EQ(frames.size(), 7u);
  EXPECT_NE(frames.at(3).find("\"volumes/"), std::string::npos)
      << "upload not kept relative: " << frames.at(3);
  fs::rename(data.str(), moved.str());
  for (int restart = 0; restart < 2; ++restart) {  // twice: the first restore changed nothing
    RunningServer again(moved.durable());
    const auto restored = again.server().restore();
    ASSERT_EQ(restored.size(), 1u);
    EXPECT_TRUE(restored[0].problem.empty()) << restored[0].problem;
    EXPECT_FALSE(restored[0].stalledAt.has_value());
    auto client = again.client();
    EXPECT_EQ(sceneJson(client, id)["version"], 7);
    EXPECT_TRUE(meshBin(client, id) == meshes.back());
    EXPECT_EQ(sceneJson(client, id)["volumes"].size(), 1u);
    EXPECT_EQ(client.Get(("/api/scenes/" + id + "/image?width=8&height=6").c_str())->status, 200);
  }
  EXPECT_EQ(journaledFrames(moved.str()), frames);
}

// A frame garbled in the file (its checksum fails), or one that reads but no longer applies:
// the scene stalls at the version before, is served there byte for byte, refuses edits with 409,
// and says so in health and the scene list; every frame stays in the journal, restart after
// restart.
TEST(JournalFaults, AGarbledOrUnappliableFrameStallsTheSceneAndKeepsEveryFrame) {
  for (const bool keepChecksum : {false, true}) {
    SCOPED_TRACE(keepChecksum ? "a frame that no longer applies"
                              : "a frame that fails its checksum");
    TempDataDir data;
    std::vector<std::string> meshes;
    std::string id;
    {
      RunningServer running(data.durable());
      auto client = running.client();
      id = addTiny(client);
      meshes = dragBox(client, id, 6, 3);
    }
    if (keepChecksum) {
      const std::string frame = R"({"edits":[{"op":"remove","id":"no_such_object"}]})";
      execSql(data.str(), "UPDATE frames SET frame = '" + frame +
                              "', crc = " + std::to_string(SceneJournal::frameChecksum(4, frame)) +
                              " WHERE version = 4");
    } else {
      execSql(
          data.str(),
          "UPDATE frames SET frame = CAST('{\"edits\":[{\"op\":\"move\",\"id\":\"box\"}' AS BLOB) "
          "WHERE version = 4");
    }
    const auto kept = journaledFrames(data.str());
    ASSERT_EQ(kept.size(), 6u);
    for (int restart = 0; restart < 2; ++restart) {
      RunningServer again(data.durable());
      const auto restored = again.server().restore();
      ASSERT_EQ(restored.size(), 1u);
      ASSERT_TRUE(restored[0].stalledAt.has_value()) << restored[0].problem;
      EXPECT_EQ(*restored[0].stalledAt, 3u);
      EXPECT_NE(restored[0].problem.find("frame 4"), std::string::npos) << restored[0].problem;
      auto client = again.client();
      const json scene = sceneJson(client, id);
      EXPECT_EQ(scene["version"], 3);
      EXPECT_EQ(scene["stalled_at"], 3);
      EXPECT_TRUE(meshBin(client, id) == meshes[3])
          << "the stalled version is not served byte for byte";
      const auto edit =
          postJson(client, "/api/scenes/" + id + "/edits", moveFrame("box", 0, 0.5, 0));
      EXPECT_EQ(edit->status, 409) << edit->body;
      EXPECT_EQ(bodyJson(edit)["error"]["code"], "scene_stalled");
      const json health = bodyJson(client.Get("/api/health"));
      EXPECT_EQ(health["status"], "degraded");
      ASSERT_EQ(health["journal"]["scene_problems"].size(), 1u) << health.dump();
      EXPECT_EQ(health["journal"]["scene_problems"][0]["stalled_at"], 3);
      const json list = bodyJson(client.Get("/api/scenes"))["scenes"];
      ASSERT_EQ(list.size(), 1u);
      EXPECT_EQ(list[0]["stalled_at"], 3);
      EXPECT_EQ(journaledFrames(data.str()), kept) << "restore changed the journal";
    }
  }
}

TEST(JournalFaults, ADataDirectoryRemovedWhileServingMakesEdits503AndHealthNotDurable) {
  TempDataDir data;
  RunningServer running(data.durable());
  auto client = running.client();
  const std::string id = addTiny(client);
  dragBox(client, id, 1, 4);
  EXPECT_EQ(bodyJson(client.Get("/api/health"))["durable"], true);
  fs::remove_all(data.str());
  const auto edit = postJson(client, "/api/scenes/" + id + "/edits", moveFrame("box", 1, 0.5, 1));
  ASSERT_TRUE(edit);
  EXPECT_EQ(edit->status, 503) << edit->body;
  EXPECT_EQ(bodyJson(edit)["error"]["code"], "journal_failed");
  EXPECT_EQ(sceneJson(client, id)["version"], 1);
  const auto created = postJson(client, "/api/scenes?name=more", tinyScene());
  EXPECT_EQ(created->status, 503) << created->body;
  const auto upload = client.Post(("/api/scenes/" + id + "/volumes?name=smoke.nrrd").c_str(),
                                  smokeBytes(), "application/octet-stream");
  EXPECT_EQ(upload->status, 503) << upload->body;
  EXPECT_FALSE(fs::exists(data.str())) << "the upload made the data directory again";
  const json health = bodyJson(client.Get("/api/health"));
  EXPECT_EQ(health["durable"], false);
  EXPECT_EQ(health["status"], "degraded");
  EXPECT_NE(health["journal"]["durability"], "ok");
}

TEST(JournalFaults, OneServerPerDataDirectoryAndPort) {
  TempDataDir data;
  RunningServer first(data.durable());
  try {
    HttpServer second(data.durable());
    FAIL() << "a second server opened the same data directory";
  } catch (const DataDirectoryLocked& error) {
    EXPECT_NE(std::string(error.what()).find("in use"), std::string::npos) << error.what();
  }
  EXPECT_EQ(bodyJson(first.client().Get("/api/health"))["durable"], true);
  // No SO_REUSEPORT: the same port cannot be bound twice.
  ServerOptions samePort = RunningServer::loopback();
  samePort.port = first.port();
  HttpServer other(samePort);
  EXPECT_THROW(other.bind(), std::runtime_error);
  // The first still serves and journals.
  auto client = first.client();
  const std::string id = addTiny(client);
  dragBox(client, id, 1, 6);
  EXPECT_EQ(journaledFrames(data.str()).size(), 1u);
}

TEST(JournalFaults, ADamagedDatabaseIsLoudNeverSilent) {
  TempDataDir data;
  std::vector<std::string> meshes;
  std::string id;
  {
    RunningServer running(data.durable());
    auto client = running.client();
    id = addTiny(client);
    meshes = dragBox(client, id, 40, 5);
  }
  // Garbage over the middle of the main file (after the last connection closed, the WAL was
  // checkpointed into it).
  const std::string file = data.str() + "/journal.sqlite3";
  const auto size = fs::file_size(file);
  ASSERT_GE(size, 2u * 4096);
  {
    FILE* f = std::fopen(file.c_str(), "r+b");
    ASSERT_TRUE(f);
    std::fseek(f, long(std::max<uintmax_t>(size / 2, 4096 + 1024)), SEEK_SET);
    const std::string junk(2048, '\x5a');
    std::fwrite(junk.data(), 1, junk.size(), f);
    std::fclose(f);
  }
  std::unique_ptr<RunningServer> again;
  try {
    again = std::make_unique<RunningServer>(data.durable());
  } catch (const std::exception& error) {
    SUCCEED() << "refused to start, loudly: " << error.what();
    return;
  }
  const auto restored = again->server().restore();
  auto client = again->client();
  const json health = bodyJson(client.Get("/api/health"));
  const bool everything = restored.size() == 1 && restored[0].problem.empty() &&
                          sceneJson(client, id)["version"] == 40 &&
                          meshBin(client, id) == meshes.back();
  if (!everything) {
    EXPECT_EQ(health["status"], "degraded") << "lost data silently: " << health.dump();
  }
  EXPECT_NE(health["journal"]["integrity"], "ok") << health.dump();
}

// A volume upload that cannot be written whole (a full disk: here a file-size limit, EFBIG) is a
// 503 that acknowledges nothing and leaves no file behind; the next upload goes through.
TEST(JournalFaults, AnUploadOnAFullDiskIs503AndLeavesNoFile) {
  TempDataDir data;
  RunningServer running(data.durable());
  auto client = running.client();
  const std::string id = addTiny(client);
  dragBox(client, id, 1, 9);
  const std::string bytes = smokeBytes();
  const fs::path volumes = fs::path(data.str()) / "volumes";
  auto filesIn = [&] {
    size_t n = 0;
    if (fs::is_directory(volumes))
      for ([[maybe_unused]] const auto& entry : fs::directory_iterator(volumes)) ++n;
    return n;
  };
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old), 0);
  const auto oldSignal = std::signal(SIGXFSZ, SIG_IGN);  // write() then fails with EFBIG
  rlimit small = old;
  small.rlim_cur = bytes.size() / 2;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  const auto full = client.Post(("/api/scenes/" + id + "/volumes?name=smoke.nrrd").c_str(), bytes,
                                "application/octet-stream");
  setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, oldSignal);
  ASSERT_TRUE(full);
  EXPECT_EQ(full->status, 503) << full->body;
  EXPECT_EQ(bodyJson(full)["error"]["code"], "journal_failed");
  EXPECT_EQ(filesIn(), 0u) << "a partial upload was left behind";
  EXPECT_EQ(sceneJson(client, id)["version"], 1);
  const auto fine = client.Post(("/api/scenes/" + id + "/volumes?name=smoke.nrrd").c_str(), bytes,
                                "application/octet-stream");
  EXPECT_EQ(fine->status, 201) << fine->body;
  EXPECT_EQ(filesIn(), 1u);
}

// A write-ahead log left behind (as after a kill -9): intact, it restores everything and says
// nothing; with a byte of an early frame changed, SQLite would silently drop every later commit,
// so the start says so (log, health `integrity`, status degraded) and keeps a copy of the log.
TEST(JournalFaults, ADamagedWriteAheadLogIsLoudAndKeptAside) {
  for (const bool damage : {false, true}) {
    SCOPED_TRACE(damage ? "damaged log" : "intact log");
    TempDataDir data;
    std::vector<std::string> meshes;
    std::string id;
    sqlite3* holder = nullptr;  // keeps the log: the server's close is then not the last one
    {
      RunningServer running(data.durable());
      auto client = running.client();
      id = addTiny(client);
      ASSERT_EQ(sqlite3_open((data.str() + "/journal.sqlite3").c_str(), &holder), SQLITE_OK);
      ASSERT_EQ(sqlite3_exec(holder, "SELECT COUNT(*) FROM scenes", nullptr, nullptr, nullptr),
                SQLITE_OK);
      meshes = dragBox(client, id, 12, 8);
    }
    sqlite3_db_config(holder, SQLITE_DBCONFIG_NO_CKPT_ON_CLOSE, 1, nullptr);
    sqlite3_close(holder);
    const std::string wal = data.str() + "/journal.sqlite3-wal";
    ASSERT_GT(fs::file_size(wal), 32u + 6 * (24 + 4096)) << "no log left behind";
    if (damage) {
      FILE* f = std::fopen(wal.c_str(), "r+b");
      ASSERT_TRUE(f);
      std::fseek(f, long(32 + 2 * (24 + 4096) + 24 + 100), SEEK_SET);  // in frame 3's page
      const int byte = std::fgetc(f);
      std::fseek(f, -1, SEEK_CUR);
      std::fputc(byte ^ 0xff, f);
      std::fclose(f);
    }
    RunningServer again(data.durable());
    const auto restored = again.server().restore();
    auto client = again.client();
    const json health = bodyJson(client.Get("/api/health"));
    if (!damage) {
      EXPECT_EQ(health["status"], "ok") << health.dump();
      EXPECT_EQ(sceneJson(client, id)["version"], 12);
      EXPECT_TRUE(meshBin(client, id) == meshes.back());
      continue;
    }
    EXPECT_EQ(health["status"], "degraded") << health.dump();
    EXPECT_NE(health["journal"]["integrity"].get<std::string>().find("write-ahead log"),
              std::string::npos)
        << health.dump();
    bool copied = false;
    for (const auto& entry : fs::directory_iterator(data.str()))
      copied |= entry.path().filename().string().rfind("journal.sqlite3-wal.damaged-", 0) == 0;
    EXPECT_TRUE(copied) << "the damaged log was not kept aside";
    for (const RestoredScene& scene : restored)
      EXPECT_TRUE(!scene.served || scene.stalledAt.has_value())
          << "a scene from a damaged log takes edits";
  }
}

}  // namespace
}  // namespace penumbra::server::test
