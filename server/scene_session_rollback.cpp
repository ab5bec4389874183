// SceneSession's engine rollback: the log that lets it rebuild its engine exactly as it was
// before a frame that failed mid-apply, and that rebuild (not the journal's restore at start,
// journal_write_restore.cpp).
#include <cstdio>

#include "server/scene_session.h"

namespace penumbra::server {

namespace {

// Frames kept for an exact rollback. A drag frame replays in ~2 ms (README "Incremental
// edits"), so a rollback costs a build plus at most a few seconds; past this a rollback
// rebuilds the published scene instead (same scene and version, fresh DM-trees).
constexpr size_t kMaxReplayFrames = 1000;

}  // namespace

void SceneSession::noteApplied(const Frame& frame, const FrameResult& result, const Scene& scene) {
  if (result.fullRebuild) {  // the engine is now a fresh build of `scene`: a new base
    Scene base = scene;      // copied first: a failed copy leaves the old base whole
    baseScene_ = std::move(base);
    baseVersion_ = result.version;
    sinceBase_.clear();
    replayable_ = true;
  } else if (replayable_ && sinceBase_.size() < kMaxReplayFrames) {
    sinceBase_.push_back(frame);
  } else {
    replayable_ = false;
    sinceBase_ = {};
  }
}

void SceneSession::rollBackEngine(const SceneSnapshot& published) {
  engine_.reset();
  if (replayable_) {
    try {
      auto engine = std::make_unique<Engine>(baseScene_, settings_);
      engine->setVersion(baseVersion_);
      for (const Frame& frame : sinceBase_) applyFrame(*engine, frame);
      if (engine->version() == published.version) {
        engine_ = std::move(engine);
        return;
      }
      std::fprintf(stderr, "penumbra serve: scene '%s': replay reached version %llu, not %llu\n",
                   id_.c_str(), (unsigned long long)engine->version(),
                   (unsigned long long)published.version);
    } catch (const std::bad_alloc&) {
      throw;  // engine_ stays null; the next frame replays again (exact once memory is back)
    } catch (const std::exception& error) {
      std::fprintf(stderr, "penumbra serve: scene '%s': replay failed: %s\n", id_.c_str(),
                   error.what());
    }
  }
  // No exact replay: a fresh build of what is published, which becomes the new base.
  buildBase(published.scene, published.version);
}

}  // namespace penumbra::server
