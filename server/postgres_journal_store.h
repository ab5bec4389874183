// The journal's PostgreSQL store (journal_store.h; docs/SERVER.md "Durability"): the same three
// tables as the SQLite journal in a database named by a libpq connection URI, over one connection
// (libpq), uploaded volume files in the database too (volumes, their bytes in 8 MiB chunks: every
// node reads them), and the scene_leases table (scene_leases.h) whose tokens fence every write.
// Each write is a transaction committed with synchronous_commit on, so an acknowledged frame is on
// the database's disk; a lost connection is opened again on the next write or health check. Not
// thread-safe.
#pragma once

#include <string>

#include "server/journal_store.h"

struct pg_conn;

namespace penumbra::server {

class PostgresJournalStore : public JournalStore {
 public:
  // Connects to `uri` (postgresql://…) and creates the schema when missing. Throws
  // std::runtime_error naming the database when it cannot be reached.
  explicit PostgresJournalStore(const std::string& uri);
  ~PostgresJournalStore() override;
  PostgresJournalStore(const PostgresJournalStore&) = delete;
  PostgresJournalStore& operator=(const PostgresJournalStore&) = delete;

  const std::string& where() const override { return where_; }
  const std::string& integrity() const override { return integrity_; }
  const std::string& logDamage() const override { return logDamage_; }
  std::string problem(bool ask) override;

  void readScenes(const std::function<void(JournalSceneRow&&)>& row) override;
  void readFrames(const std::function<void(JournalFrameRow&&)>& row) override;
  void readSnapshots(const std::function<void(JournalSnapshotRow&&)>& row) override;
  std::optional<JournalSceneRow> sceneById(const std::string& id) override;
  void readFramesOf(int64_t key, const std::function<void(JournalFrameRow&&)>& row) override;
  void readSnapshotsOf(int64_t key, const std::function<void(JournalSnapshotRow&&)>& row) override;

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
  void configure();                       // the session's settings, after every (re)connection
  std::string connectionProblem() const;  // empty while connected

  pg_conn* conn_ = nullptr;
  std::string where_;             // the URI's place without its password
  std::string integrity_ = "ok";  // PostgreSQL checks its own pages and log
  std::string logDamage_;
};

}  // namespace penumbra::server
