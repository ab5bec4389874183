// The database under the journal (scene_journal.h): what is SQL-specific — opening it and its
// schema, one transaction per write, the statements over scenes, frames and snapshots, what its
// integrity check found. Rows go in and come out as stored; checksums, the version-gap rule and
// how many snapshots are kept are SceneJournal's, the same for every store. Not thread-safe:
// SceneJournal serialises every call behind its mutex.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra::server {

// A checksum column of a row from before checksums reads as nullopt (journal_store rows below).
struct JournalSceneRow {
  int64_t key = 0;  // assigned by insertScene
  std::string id, name;
  int64_t baseVersion = 0;
  std::string source;
  std::optional<int64_t> sourceCrc;
};

struct JournalFrameRow {
  int64_t scene = 0;  // the scene's key
  int64_t version = 0;
  std::string frame, parts;
  std::optional<int64_t> crc, partsCrc, base;
};

struct JournalSnapshotRow {
  int64_t scene = 0;
  int64_t version = 0;
  std::string source, parts;
  int64_t crc = 0;
};

// An uploaded volume file of a scene (its NRRD upload): named as the journal's texts name it,
// relative to the data directory (volumes/ID-<16 hex digits>.nrrd), its bytes and their CRC-32.
struct JournalVolumeRow {
  int64_t scene = 0;
  std::string name;
  std::string bytes;  // empty in volumesOf's rows
  int64_t size = 0;
  int64_t crc = 0;
};

// The fencing token a write of a scene owned by a lease carries (scene_leases.h): its transaction
// checks that the scene's lease still holds that token, else throws LeaseLost with nothing
// written. None: an unfenced write (SQLite, one node).
using LeaseToken = std::optional<int64_t>;

// A write refused because another node took the scene's lease over (a newer token).
class LeaseLost : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class JournalStore {
 public:
  virtual ~JournalStore() = default;

  // The journal's place for messages and /api/health: a file, or a database URI without its
  // password.
  virtual const std::string& where() const = 0;
  // "ok", or the damage found at open (SQLite's quick_check, a damaged write-ahead log).
  virtual const std::string& integrity() const = 0;
  // Committed transactions found lost at open (SQLite's write-ahead log): every scene restored
  // from such a journal is stalled. Empty for a database that keeps its own log.
  virtual const std::string& logDamage() const = 0;
  // Empty while a write can be committed; else why not (a lost database connection, which this
  // tries to open again). `ask`: also ask the database itself (a round trip: for health, not
  // before every write; a write that fails says so anyway).
  virtual std::string problem(bool ask) = 0;

  // Every row, scenes by key, frames and snapshots by (scene, version); a failure part-way
  // throws after the rows read so far were handed over.
  virtual void readScenes(const std::function<void(JournalSceneRow&&)>& row) = 0;
  virtual void readFrames(const std::function<void(JournalFrameRow&&)>& row) = 0;
  virtual void readSnapshots(const std::function<void(JournalSnapshotRow&&)>& row) = 0;
  // One scene's rows: the newest scene with this id (nullopt: none), then its frames and
  // snapshots as above. (These defaults read everything; a store with many scenes has its own.)
  virtual std::optional<JournalSceneRow> sceneById(const std::string& id);
  virtual void readFramesOf(int64_t key, const std::function<void(JournalFrameRow&&)>& row);
  virtual void readSnapshotsOf(int64_t key, const std::function<void(JournalSnapshotRow&&)>& row);

  // Each write is one committed transaction, or throws std::runtime_error with nothing written
  // (LeaseLost when `lease` is no longer the scene's token).
  virtual int64_t insertScene(const JournalSceneRow& scene, LeaseToken lease) = 0;  // the new key
  virtual void insertFrame(const JournalFrameRow& frame, LeaseToken lease) = 0;
  // Writes (or replaces) the snapshot and deletes the scene's snapshots older than the newest
  // `keep`.
  virtual void putSnapshot(const JournalSnapshotRow& snapshot, size_t keep, LeaseToken lease) = 0;
  virtual void deleteScene(int64_t key, LeaseToken lease) = 0;  // with its frames and snapshots
  virtual void renameScene(int64_t key, const std::string& name, LeaseToken lease) = 0;

  // Uploaded volume files, kept with their scene (deleteScene deletes them too). putVolume stores
  // one (replacing one of the same name), a write as above; readVolume gives it back whole
  // (nullopt: none; throws when its bytes cannot be read), volumesOf lists a scene's without their
  // bytes; deleteVolume drops one (an upload whose frame was refused).
  virtual void putVolume(const JournalVolumeRow& volume, LeaseToken lease) = 0;
  virtual std::optional<JournalVolumeRow> readVolume(int64_t scene, const std::string& name) = 0;
  virtual std::vector<JournalVolumeRow> volumesOf(int64_t scene) = 0;
  virtual void deleteVolume(int64_t scene, const std::string& name, LeaseToken lease) = 0;
};

}  // namespace penumbra::server
