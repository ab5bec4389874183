// The journal itself (scene_journal.h) on each store: rows come back byte for byte, the
// version-gap rule, checksums that catch rows changed behind its back, the snapshots kept, a
// deleted scene's rows gone, uploaded volumes kept with their scene and put back byte for byte
// wherever it is restored — the same answers from SQLite and PostgreSQL.
#include "server/scene_journal.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "temp_data_dir.h"
#include "test_journal.h"

namespace penumbra::server::test {
namespace {

class SceneJournalOnEachStore : public ::testing::TestWithParam<JournalBackend> {};

INSTANTIATE_TEST_SUITE_P(Stores, SceneJournalOnEachStore,
                         ::testing::Values(JournalBackend::Sqlite, JournalBackend::Postgres),
                         backendName);

// Seeded bytes of every value, NUL and invalid UTF-8 included.
std::string randomBytes(std::mt19937& rng, size_t size) {
  std::string bytes(size, '\0');
  for (char& byte : bytes) byte = char(rng() & 0xff);
  return bytes;
}

TEST_P(SceneJournalOnEachStore, RowsComeBackByteForByteAcrossAReopen) {
  const TestJournal data(GetParam());
  std::mt19937 rng(39);
  struct Written {
    int64_t key;
    std::string source;
    std::vector<std::pair<std::string, std::string>> frames;  // frame, parts
  };
  std::vector<Written> written;
  {
    SceneJournal journal(data.dir().str(), data.database());
    EXPECT_EQ(journal.integrity(), "ok");
    EXPECT_EQ(journal.durabilityProblem(), "");
    for (int s = 0; s < 3; ++s) {
      Written scene{0, randomBytes(rng, 1 + rng() % 5000), {}};
      scene.key = journal.addScene("scene" + std::to_string(s), "name " + std::to_string(s),
                                   scene.source, 0);
      for (uint64_t v = 1; v <= 1 + rng() % 20; ++v) {
        scene.frames.emplace_back(randomBytes(rng, rng() % 3000), randomBytes(rng, rng() % 300));
        journal.addFrame(scene.key, v, scene.frames.back().first, scene.frames.back().second,
                         v - 1);
      }
      written.push_back(std::move(scene));
    }
  }
  SceneJournal reopened(data.dir().str(), data.database());
  const auto scenes = reopened.load();
  EXPECT_EQ(reopened.loadProblem(), "");
  ASSERT_EQ(scenes.size(), written.size());
  for (size_t s = 0; s < scenes.size(); ++s) {
    EXPECT_EQ(scenes[s].key, written[s].key);
    EXPECT_EQ(scenes[s].id, "scene" + std::to_string(s));
    EXPECT_TRUE(scenes[s].source == written[s].source);
    EXPECT_TRUE(scenes[s].sourceIntact);
    ASSERT_EQ(scenes[s].frames.size(), written[s].frames.size());
    for (size_t f = 0; f < scenes[s].frames.size(); ++f) {
      const auto& frame = scenes[s].frames[f];
      EXPECT_EQ(frame.version, f + 1);
      EXPECT_TRUE(frame.intact);
      EXPECT_TRUE(frame.frame == written[s].frames[f].first);
      EXPECT_TRUE(frame.parts == written[s].frames[f].second);
      EXPECT_EQ(frame.base, std::optional<uint64_t>(f));
    }
  }
  // The reopened journal continues each scene where it stopped.
  const Written& last = written.back();
  EXPECT_NO_THROW(reopened.addFrame(last.key, last.frames.size() + 1, "{}", "", 0));
}

TEST_P(SceneJournalOnEachStore, AVersionGapIsRefusedAndWritesNothing) {
  const TestJournal data(GetParam());
  SceneJournal journal(data.dir().str(), data.database());
  const int64_t key = journal.addScene("a", "a", "{}", 5);
  journal.addFrame(key, 6, "six", "", 5);
  for (const uint64_t wrong : {6u, 8u, 5u}) {
    try {
      journal.addFrame(key, wrong, "wrong", "", 5);
      ADD_FAILURE() << "version " << wrong << " after 6 was journaled";
    } catch (const std::runtime_error& error) {
      EXPECT_NE(std::string(error.what()).find("does not follow the last journaled version 6"),
                std::string::npos)
          << error.what();
    }
  }
  EXPECT_EQ(data.sqlText("SELECT frame FROM frames ORDER BY version"), "six");
  journal.addFrame(key, 7, "seven", "", 5);
  EXPECT_EQ(data.sqlText("SELECT version FROM frames ORDER BY version"), "6,7");
  EXPECT_THROW(journal.addFrame(key + 1, 1, "x", "", 0), std::runtime_error);  // no such scene
}

TEST_P(SceneJournalOnEachStore, ChecksumsCatchRowsChangedBehindItsBack) {
  const TestJournal data(GetParam());
  {
    SceneJournal journal(data.dir().str(), data.database());
    const int64_t key = journal.addScene("a", "a", R"({"scene":1})", 0);
    for (uint64_t v = 1; v <= 3; ++v)
      journal.addFrame(key, v, "frame " + std::to_string(v), "parts " + std::to_string(v), 0);
    journal.addSnapshot(key, 2, "snapshot source", "snapshot parts");
  }
  data.sql("UPDATE frames SET frame = 'frame 9' WHERE version = 2");
  data.sql("UPDATE frames SET parts = 'parts 9' WHERE version = 3");
  data.sql("UPDATE scenes SET source = 'garbled'");
  data.sql("UPDATE snapshots SET parts = 'garbled'");
  {
    SceneJournal journal(data.dir().str(), data.database());
    const auto scenes = journal.load();
    ASSERT_EQ(scenes.size(), 1u);
    EXPECT_FALSE(scenes[0].sourceIntact);
    ASSERT_EQ(scenes[0].frames.size(), 3u);
    EXPECT_TRUE(scenes[0].frames[0].intact);
    EXPECT_FALSE(scenes[0].frames[1].intact);
    EXPECT_TRUE(scenes[0].frames[2].intact);   // only its part changes were damaged:
    EXPECT_EQ(scenes[0].frames[2].parts, "");  // dropped, so the scene replays frame by frame
    EXPECT_EQ(scenes[0].frames[0].parts, "parts 1");
    ASSERT_EQ(scenes[0].snapshots.size(), 1u);
    EXPECT_FALSE(scenes[0].snapshots[0].intact);
  }
  // Rows from before checksums (none stored) read as intact.
  data.sql("UPDATE frames SET crc = NULL WHERE version = 2");
  data.sql("UPDATE scenes SET source_crc = NULL");
  SceneJournal journal(data.dir().str(), data.database());
  const auto scenes = journal.load();
  ASSERT_EQ(scenes.size(), 1u);
  EXPECT_TRUE(scenes[0].sourceIntact);
  EXPECT_TRUE(scenes[0].frames.at(1).intact);
  EXPECT_EQ(scenes[0].frames.at(1).frame, "frame 9");
}

TEST_P(SceneJournalOnEachStore, KeepsTheNewestSnapshotsAndDeletesASceneWithItsRows) {
  const TestJournal data(GetParam());
  SceneJournal journal(data.dir().str(), data.database());
  const int64_t kept = journal.addScene("kept", "kept", "{}", 0);
  const int64_t gone = journal.addScene("gone", "gone", "{}", 0);
  for (uint64_t v = 1; v <= 9; ++v) {
    journal.addFrame(kept, v, "k", "", 0);
    journal.addFrame(gone, v, "g", "", 0);
    if (v % 2 == 0) {
      journal.addSnapshot(kept, v, "s" + std::to_string(v), "p");
      journal.addSnapshot(gone, v, "s", "p");
    }
  }
  journal.addSnapshot(kept, 8, "s8 again", "p");  // the same version again replaces it
  EXPECT_EQ(data.sqlText("SELECT version FROM snapshots WHERE scene = " + std::to_string(kept) +
                         " ORDER BY version"),
            "6,8");
  journal.removeScene(gone);
  EXPECT_EQ(data.sqlText("SELECT DISTINCT scene FROM frames"), std::to_string(kept));
  EXPECT_EQ(data.sqlText("SELECT DISTINCT scene FROM snapshots"), std::to_string(kept));
  EXPECT_THROW(journal.addFrame(gone, 10, "g", "", 0), std::runtime_error);
  const auto scenes = journal.load();
  ASSERT_EQ(scenes.size(), 1u);
  ASSERT_EQ(scenes[0].snapshots.size(), SceneJournal::kSnapshotsKept);
  EXPECT_EQ(scenes[0].snapshots[1].source, "s8 again");
  EXPECT_TRUE(scenes[0].snapshots[1].intact);
  EXPECT_EQ(scenes[0].frames.size(), 9u);
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// An upload whose frame was acknowledged comes back byte for byte where its scene is restored
// (more than two 8 MiB chunks of PostgreSQL's); one no frame names is not fetched; a
// copy whose checksum fails is fetched again where the database holds the bytes, and said where
// the copy is the store's own file (SQLite); deleting the scene deletes its uploads.
TEST_P(SceneJournalOnEachStore, AnUploadComesBackByteForByteWhereverItsSceneIsRestored) {
  const TestJournal data(GetParam());
  std::mt19937 rng(39);
  const std::string named = "volumes/a-00000000000000a1.nrrd";
  const std::string unnamed = "volumes/a-00000000000000b2.nrrd";
  const std::string bytes = randomBytes(rng, (size_t(17) << 20) + rng() % 1000);
  {
    SceneJournal journal(data.dir().str(), data.database());
    const int64_t key = journal.addScene("a", "a", "{}", 0);
    journal.addVolume(key, named, bytes);
    EXPECT_TRUE(fileBytes(data.dir().str() + "/" + named) == bytes);  // this node's copy
    journal.addVolume(key, unnamed, randomBytes(rng, 100));           // its frame never committed
    journal.addFrame(
        key, 1, R"({"edits":[{"op":"add_volume","volume":{"file":")" + named + R"("}}]})", "", 0);
  }
  // Restored on another node: a fresh data directory on PostgreSQL (the database holds
  // everything); the same one with SQLite, whose journal is a file of it.
  const TempDataDir other;
  const std::string dir = data.database().empty() ? data.dir().str() : other.str();
  std::filesystem::remove(dir + "/" + unnamed);
  SceneJournal journal(dir, data.database());
  auto scenes = journal.load();
  ASSERT_EQ(scenes.size(), 1u);
  EXPECT_EQ(journal.fetchVolumes(scenes[0]), "");
  EXPECT_TRUE(fileBytes(dir + "/" + named) == bytes);
  EXPECT_FALSE(std::filesystem::exists(dir + "/" + unnamed));
  EXPECT_EQ(data.sqlText("SELECT size FROM volumes ORDER BY name"),
            std::to_string(bytes.size()) + ",100");

  std::string damaged = bytes;
  damaged[rng() % damaged.size()] ^= 0x10;
  std::ofstream(dir + "/" + named, std::ios::binary) << damaged;
  const std::string problem = journal.fetchVolumes(scenes[0]);
  if (GetParam() == JournalBackend::Postgres) {
    EXPECT_EQ(problem, "");
    EXPECT_TRUE(fileBytes(dir + "/" + named) == bytes);
  } else {
    EXPECT_NE(problem.find(named + " fails its checksum"), std::string::npos) << problem;
  }

  journal.removeScene(scenes[0].key);
  EXPECT_EQ(data.sqlText("SELECT COUNT(*) FROM volumes"), "0");
  if (GetParam() == JournalBackend::Postgres)
    EXPECT_EQ(data.sqlText("SELECT COUNT(*) FROM volume_chunks"), "0");
  else
    EXPECT_FALSE(std::filesystem::exists(dir + "/" + named));
}

// A stored checksum that no longer matches the stored bytes is said, not served; an upload whose
// frame was refused is removed with its copy; names outside volumes/ are refused, nothing
// written; a scene no longer journaled stores nothing.
TEST_P(SceneJournalOnEachStore, UploadChecksumsNamesAndRemovals) {
  const TestJournal data(GetParam());
  std::mt19937 rng(40);
  SceneJournal journal(data.dir().str(), data.database());
  const int64_t key = journal.addScene("b", "b", "{}", 0);
  const std::string kept = "volumes/b-00000000000000c3.nrrd";
  const std::string refused = "volumes/b-00000000000000d4.nrrd";
  journal.addVolume(key, kept, randomBytes(rng, 5000));
  journal.addVolume(key, refused, randomBytes(rng, 5000));
  journal.removeVolume(key, refused);
  EXPECT_FALSE(std::filesystem::exists(data.dir().str() + "/" + refused));
  EXPECT_EQ(data.sqlText("SELECT name FROM volumes"), kept);
  for (const std::string bad :
       {"../b.nrrd", "volumes/../b.nrrd", "volumes/", "b.nrrd", "volumes/x/b.nrrd", "/tmp/b.nrrd"})
    EXPECT_THROW(journal.addVolume(key, bad, "x"), std::runtime_error) << bad;
  EXPECT_THROW(journal.addVolume(key + 1, "volumes/c.nrrd", "x"), std::runtime_error);
  EXPECT_EQ(data.sqlText("SELECT name FROM volumes"), kept);

  journal.addFrame(key, 1, "names " + kept, "", 0);
  data.sql("UPDATE volumes SET crc = crc + 1");
  if (GetParam() == JournalBackend::Postgres)  // this node's copy gone: the database's bytes read
    std::filesystem::remove(data.dir().str() + "/" + kept);
  const auto scenes = journal.load();
  ASSERT_EQ(scenes.size(), 1u);
  const std::string problem = journal.fetchVolumes(scenes[0]);
  EXPECT_NE(problem.find(kept + " fails its checksum"), std::string::npos) << problem;
}

}  // namespace
}  // namespace penumbra::server::test
