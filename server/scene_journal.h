// The durable record of served scenes (README "Durability"): each scene's source JSON and every
// acknowledged frame, committed before the server answers, and periodic snapshots (a scene and its
// mesh at one version) that bound what a restart replays. Kept in a JournalStore: SQLite in the
// data directory (WAL, synchronous=FULL), or a PostgreSQL database; checksums, the version-gap
// rule and the snapshots kept are this class's, the same on both. Thread-safe (one mutex around
// the store).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "server/journal_store.h"

namespace penumbra::server {

class DataDirectory;

class SceneJournal {
 public:
  // What load() returns for one scene: enough to rebuild it and replay its frames in order.
  struct StoredScene {
    int64_t key = 0;  // the journal's own key: ids are reused after a DELETE, keys never
    std::string id, name;
    std::string source;  // scene JSON v1 (sceneToJson of the scene as created)
    uint64_t baseVersion = 0;
    bool sourceIntact = true;  // its checksum matches (or it has none: a journal from before them)
    bool complete = true;      // false: reading its frames failed part-way (loadProblem())
    struct StoredFrame {
      uint64_t version = 0;
      std::string frame;   // frame JSON as received
      std::string parts;   // what it did to the served mesh (part_changes.h); empty: not recorded
                           // (or its checksum failed)
      bool intact = true;  // the frame's checksum matches (or it has none)
      // The version whose fresh build the engine that applied it came from (SceneSession's
      // base: the scene's creation, a rebuilding light edit, a snapshot); none in older rows.
      std::optional<uint64_t> base;
    };
    std::vector<StoredFrame> frames;  // in version order
    // The scene at a version, as a restart may start from it instead of `source`: the scene
    // JSON (files as the journal names them) and its mesh parts (stored_parts.h).
    struct StoredSnapshot {
      uint64_t version = 0;
      std::string source, parts;
      bool intact = true;  // its checksum matches
    };
    std::vector<StoredSnapshot> snapshots;  // in version order (the newest kSnapshotsKept)
  };

  // Snapshots kept per scene: the newest, and one to fall back on should it be damaged.
  static constexpr size_t kSnapshotsKept = 2;

  // Locks DIR (one server per data directory: DataDirectoryLocked; uploaded files live there
  // whatever the store) and opens the journal, creating DIR and the schema: DIR/journal.sqlite3,
  // SQLite's quick_check run (what it found: integrity()); or, when `database` is a libpq
  // connection URI (postgresql://…), that PostgreSQL database. Throws std::runtime_error.
  explicit SceneJournal(const std::string& dir, const std::string& database = "");
  ~SceneJournal();
  SceneJournal(const SceneJournal&) = delete;
  SceneJournal& operator=(const SceneJournal&) = delete;

  const std::string& path() const;       // the journal file, or the database URI without password
  const std::string& directory() const;  // the data directory, absolute
  // "ok", or what was found damaged at open: committed frames of the write-ahead log that SQLite
  // would ignore (wal_check.h), what PRAGMA quick_check reported.
  const std::string& integrity() const;
  // Committed transactions of the write-ahead log SQLite ignored at open (wal_check.h): the scenes
  // restored from it may lack acknowledged frames, so restore stalls them all.
  const std::string& logDamage() const;
  // Empty while commits are durable; else why not (the data directory removed, replaced or
  // unwritable, the journal file gone, the database unreachable): every write then throws without
  // writing. A database is asked (a round trip), unless a write is in flight: that write answers
  // for itself.
  std::string durabilityProblem() const;
  // Read only: restore never changes the journal. A checksum mismatch marks the frame (or the
  // scene's source) not intact; a read error part-way is `loadProblem` (the scenes read so far
  // come back; the scene being read and those after it are flagged by `complete = false`).
  std::vector<StoredScene> load();
  const std::string& loadProblem() const { return loadProblem_; }
  // One scene, as load() would return it: the newest journaled scene with this id (nullopt:
  // none), for a node that took its lease over (scene_leases.h). Its writes from now on carry
  // `lease` as their fencing token. A read error part-way leaves it `complete = false`.
  std::optional<StoredScene> loadScene(const std::string& id, int64_t lease);
  // Whether a scene with this id is journaled (a node of a cluster picking a new scene's id).
  bool hasScene(const std::string& id);
  // Scene `key`'s writes carry `lease` from now on (its lease taken at start-up).
  void holdLease(int64_t key, int64_t lease);
  // Forgets scene `key` (a node that gave its lease up): its writes fail until loadScene again.
  void forgetScene(int64_t key);
  // Each call is one committed transaction; throws std::runtime_error (nothing written) on failure,
  // and before writing anything when durabilityProblem() is not empty; LeaseLost when another
  // node took the scene's lease over.
  // `lease`: the token of the scene's lease (scene_leases.h) its writes carry; none with SQLite.
  int64_t addScene(const std::string& id, const std::string& name, const std::string& source,
                   uint64_t baseVersion, LeaseToken lease = {});
  // `version` must follow the scene's last journaled version by exactly one: a gap means an
  // earlier frame was applied but never journaled, and the scene takes no more frames.
  // `parts`: the frame's PartChanges as text, which lets a restart mesh once
  // (journal_write_restore.cpp).
  // `base`: StoredFrame::base.
  void addFrame(int64_t key, uint64_t version, const std::string& frame, const std::string& parts,
                uint64_t base);
  // Records the scene at `version` (StoredSnapshot) and drops its snapshots older than the
  // newest kSnapshotsKept; frames are never dropped (docs/SERVER.md "Snapshots").
  void addSnapshot(int64_t key, uint64_t version, const std::string& source,
                   const std::string& parts);
  void removeScene(int64_t key);
  // The scene's new name (scene lists and restarts show it).
  void renameScene(int64_t key, const std::string& name);

  // Uploaded volume files (journal_volumes.cpp; docs/SERVER.md "Volumes on many nodes"). `name`
  // is the file as the journal's texts name it, relative to the data directory
  // (volumes/FILE; anything else throws). addVolume stores the bytes with scene `key` — one
  // committed write, fenced like its frames, thrown as they are — and leaves this node's copy at
  // DIR/name before returning.
  void addVolume(int64_t key, const std::string& name, const std::string& bytes);
  // Drops an upload no frame came to name (its frame was refused): the stored bytes and this
  // node's copy.
  void removeVolume(int64_t key, const std::string& name);
  // Puts in DIR every stored upload of `scene` that its source, frames or snapshots name, as
  // stored: a copy whose size and CRC match is kept, any other fetched from the store and checked.
  // Returns what failed ("" when every one is in place); never throws.
  std::string fetchVolumes(const StoredScene& scene);
  // An upload's checksum: zlib's CRC-32 over its bytes.
  static uint32_t volumeChecksum(const std::string& bytes);

  // The checksum journaled with a frame: zlib's CRC-32 over its version and JSON. (Its part
  // changes have their own; a mismatch there only drops them: the scene replays frame by frame.)
  static uint32_t frameChecksum(uint64_t version, const std::string& frame);
  // A snapshot's: CRC-32 over its version, source and parts.
  static uint32_t snapshotChecksum(uint64_t version, const std::string& source,
                                   const std::string& parts);

 private:
  // Throws std::runtime_error naming what durabilityProblem() would (without asking the
  // database: a write that cannot commit fails anyway). Call with mutex_ held.
  void requireDurable() const;
  // Throws when the store cannot be reached: a lost connection is opened again first (a read
  // after the database came back). Call with mutex_ held.
  void requireReachable() const;
  LeaseToken leaseOf(int64_t key) const;  // call with mutex_ held

  mutable std::mutex mutex_;
  std::unique_ptr<DataDirectory> dir_;  // locked first, released last
  std::unique_ptr<JournalStore> store_;
  std::string loadProblem_;
  std::map<int64_t, uint64_t> lastVersion_;  // per scene key
  std::map<int64_t, int64_t> leases_;        // per scene key: the lease token its writes carry
};

}  // namespace penumbra::server
