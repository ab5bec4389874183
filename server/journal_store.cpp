#include "server/journal_store.h"

namespace penumbra::server {

std::optional<JournalSceneRow> JournalStore::sceneById(const std::string& id) {
  std::optional<JournalSceneRow> newest;
  readScenes([&](JournalSceneRow&& row) {
    if (row.id == id) newest = std::move(row);  // by key: the last is the newest
  });
  return newest;
}

void JournalStore::readFramesOf(int64_t key, const std::function<void(JournalFrameRow&&)>& row) {
  readFrames([&](JournalFrameRow&& frame) {
    if (frame.scene == key) row(std::move(frame));
  });
}

void JournalStore::readSnapshotsOf(int64_t key,
                                   const std::function<void(JournalSnapshotRow&&)>& row) {
  readSnapshots([&](JournalSnapshotRow&& snapshot) {
    if (snapshot.scene == key) row(std::move(snapshot));
  });
}

}  // namespace penumbra::server
