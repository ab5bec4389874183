// The durable record of served scenes (README "Durability"): each scene's source JSON and every
// acknowledged frame, in SQLite (WAL, synchronous=FULL), committed before the server answers.
// Thread-safe (one mutex around the connection).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::server {

class SqliteDb;

class SceneJournal {
 public:
  // What load() returns for one scene: enough to rebuild it and replay its frames in order.
  struct StoredScene {
    int64_t key = 0;  // the journal's own key: ids are reused after a DELETE, keys never
    std::string id, name;
    std::string source;  // scene JSON v1 (sceneToJson of the scene as created)
    uint64_t baseVersion = 0;
    struct StoredFrame {
      uint64_t version = 0;
      std::string frame;  // frame JSON as received
      std::string parts;  // what it did to the served mesh (part_changes.h); empty: not recorded
    };
    std::vector<StoredFrame> frames;  // in version order
  };

  // Opens DIR/journal.sqlite3, creating DIR and the schema. Throws std::runtime_error.
  explicit SceneJournal(const std::string& dir);
  ~SceneJournal();
  SceneJournal(const SceneJournal&) = delete;
  SceneJournal& operator=(const SceneJournal&) = delete;

  const std::string& path() const { return path_; }
  std::vector<StoredScene> load();
  // Each call is one committed transaction; throws std::runtime_error (nothing written) on failure.
  int64_t addScene(const std::string& id, const std::string& name, const std::string& source,
                   uint64_t baseVersion);
  // `version` must follow the scene's last journaled version by exactly one: a gap means an
  // earlier frame was applied but never journaled, and the scene takes no more frames.
  // `parts`: the frame's PartChanges as text, which lets a restart mesh once (scene_restore.cpp).
  void addFrame(int64_t key, uint64_t version, const std::string& frame, const std::string& parts);
  void removeScene(int64_t key);
  // Drops a scene's frames after `version` (those that no longer replay; see restore).
  void truncateAfter(int64_t key, uint64_t version);

 private:
  std::mutex mutex_;
  std::string path_;
  std::unique_ptr<SqliteDb> db_;
  std::map<int64_t, uint64_t> lastVersion_;  // per scene key
};

}  // namespace penumbra::server
