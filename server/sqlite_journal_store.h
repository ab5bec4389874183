// The journal's SQLite store (journal_store.h; docs/SERVER.md "Durability"): DIR/journal.sqlite3
// in WAL mode with synchronous=FULL, its write-ahead log checked (wal_check.h) and PRAGMA
// quick_check run at open, columns added to journals from before them. Not thread-safe.
#pragma once

#include <memory>
#include <string>

#include "server/journal_store.h"

namespace penumbra::server {

class SqliteDb;
class DataDirectory;

class SqliteJournalStore : public JournalStore {
 public:
  // Opens (creating) the journal file in `dir` and watches it (DataDirectory::watch). Throws
  // std::runtime_error when it cannot be opened (nothing in it changed).
  explicit SqliteJournalStore(DataDirectory& dir);
  ~SqliteJournalStore() override;

  const std::string& where() const override { return path_; }
  const std::string& integrity() const override { return integrity_; }
  const std::string& logDamage() const override { return logDamage_; }
  std::string problem(bool) override { return ""; }  // the data directory's checks cover it

  void readScenes(const std::function<void(JournalSceneRow&&)>& row) override;
  void readFrames(const std::function<void(JournalFrameRow&&)>& row) override;
  void readSnapshots(const std::function<void(JournalSnapshotRow&&)>& row) override;

  int64_t insertScene(const JournalSceneRow& scene, LeaseToken lease) override;
  void insertFrame(const JournalFrameRow& frame, LeaseToken lease) override;
  void putSnapshot(const JournalSnapshotRow& snapshot, size_t keep, LeaseToken lease) override;
  void deleteScene(int64_t key, LeaseToken lease) override;
  void renameScene(int64_t key, const std::string& name, LeaseToken lease) override;

  void putVolume(const JournalVolumeRow& volume, LeaseToken lease) override;
  std::optional<JournalVolumeRow> readVolume(int64_t scene, const std::string& name) override;
  std::vector<JournalVolumeRow> volumesOf(int64_t scene) override;
  void deleteVolume(int64_t scene, const std::string& name, LeaseToken lease) override;

 private:
  std::string fileOf(const std::string& volume) const;  // DIR/name
  void open();  // the connection, pragmas, quick_check and schema; throws SqliteError
  std::string checkWriteAheadLog() const;  // wal_check.h's finding, the log copied aside; or ""

  std::string path_;
  std::string dir_;  // the data directory
  std::string integrity_ = "ok";
  std::string logDamage_;
  std::unique_ptr<SqliteDb> db_;
};

}  // namespace penumbra::server
