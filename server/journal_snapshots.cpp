// Taking journal snapshots while serving (docs/SERVER.md "Snapshots"): at every
// snapshotEvery-th version the scene's engine becomes a fresh build of the scene as the snapshot
// records it, and the journal keeps that scene and the served parts. A restart then builds the
// same scene and replays only the frames after it (journal_write_restore.cpp).
#include <cstdio>

#include "server/http_server.h"
#include "server/journaled_text.h"
#include "server/stored_parts.h"

namespace penumbra::server {

void HttpServer::snapshotIfDue(SceneSession& session, uint64_t version) {
  if (!journal_ || options_.snapshotEvery == 0 || version == 0 ||
      version % options_.snapshotEvery != 0)
    return;
  int64_t key = 0;
  {
    std::lock_guard lock(scenesMutex_);
    const auto it = journalKeys_.find(&session);
    if (it == journalKeys_.end()) return;  // deleted meanwhile
    key = it->second;
  }
  const std::string& dir = journal_->directory();
  try {
    // The scene, not the frames, is what differs: so the engine must be the build a restart
    // makes. Its next frame journals this version as its base, so even without the snapshot
    // row (not written, or damaged) a replay builds afresh here too.
    const std::shared_ptr<const SceneSnapshot> at =
        session.rebase([&](const Scene& scene) { return journaledScene(scene, dir); });
    if (at->version != version) return;  // (the caller holds the scene's turn: never)
    journal_->addSnapshot(key, at->version, journaledSceneText(at->scene, dir),
                          encodeStoredParts(*at));
  } catch (const std::exception& error) {
    std::fprintf(stderr, "penumbra serve: scene '%s': no snapshot at version %llu (%s)\n",
                 session.id().c_str(), (unsigned long long)version, error.what());
  }
}

}  // namespace penumbra::server
