// The server's side of the journal (README "Durability"): frames and deletions recorded before
// they are acknowledged, and every journaled scene brought back at start.
#include <chrono>
#include <cstdio>

#include "protocol/edits_json.h"
#include "protocol/json_text.h"
#include "protocol/scene_json.h"
#include "protocol/volume_json.h"
#include "server/api_errors.h"
#include "server/http_server.h"
#include "server/part_changes.h"

namespace penumbra::server {

namespace {

ApiError journalError(const std::string& what, const std::exception& error) {
  return ApiError(503, error_code::kJournalFailed, "",
                  "the journal could not record " + what + " (" + error.what() +
                      "); nothing was acknowledged");
}

}  // namespace

void HttpServer::journalFrame(const SceneSession& session, const SceneSnapshot& next,
                              const std::string& frame) {
  if (!journal_) return;
  int64_t key = 0;
  {
    std::lock_guard lock(scenesMutex_);
    const auto it = journalKeys_.find(&session);
    if (it == journalKeys_.end())
      throw ApiError(404, error_code::kNotFound, "id", "the scene was deleted");
    key = it->second;
  }
  try {
    journal_->addFrame(key, next.version, frame, partChangesText(partChangesOf(next)));
  } catch (const std::exception& error) {
    // Nothing is published and SceneSession::apply undoes the frame in the engine (atomic
    // frames): the scene stays at its last acknowledged version and the frame may be sent again.
    throw journalError("the frame; it was not applied", error);
  }
}

void HttpServer::journalRemove(const SceneSession& session) {
  if (!journal_) return;
  int64_t key = 0;
  {
    std::lock_guard lock(scenesMutex_);
    const auto it = journalKeys_.find(&session);
    if (it == journalKeys_.end()) return;  // a concurrent DELETE got there first
    key = it->second;
  }
  try {
    journal_->removeScene(key);
  } catch (const std::exception& error) {
    throw journalError("the deletion", error);
  }
  std::lock_guard lock(scenesMutex_);
  journalKeys_.erase(&session);
}

namespace {

using StoredScene = SceneJournal::StoredScene;

std::shared_ptr<SceneSession> freshSession(const StoredScene& stored, const EngineSettings& settings) {
  // The journal wrote volume files as absolute paths (sceneToJson), and only scene files
  // loaded by the operator can hold volumes: reading them again is safe.
  const protocol::VolumeFiles volumeFiles;
  return std::make_shared<SceneSession>(
      stored.id, stored.name,
      protocol::sceneFromJson(
          protocol::parseJsonText(stored.source, stored.source.size(), protocol::kMaxJsonDepth),
          &volumeFiles),
      settings);
}

Frame storedFrame(const SceneSession& session, const std::string& text) {
  const auto materials = session.snapshot()->scene.materials();  // edits change no material
  // add_volume frames name files the server stored itself (POST .../volumes), as absolute paths.
  const protocol::VolumeFiles volumeFiles;
  return protocol::frameFromJson(
      protocol::parseJsonText(text, text.size(), protocol::kMaxJsonDepth), &materials,
      &volumeFiles);
}

// Every frame through the engine, meshed once at the end (SceneSession::replayJournaled):
// possible when each frame's part changes were journaled (journals before them: no).
bool replayAtOnce(SceneSession& session, const StoredScene& stored, RestoredScene& report) {
  std::vector<SceneSession::JournaledFrame> frames;
  for (const SceneJournal::StoredScene::StoredFrame& frame : stored.frames) {
    if (frame.parts.empty()) return false;
    frames.push_back({storedFrame(session, frame.frame), frame.version,
                      partChangesFromText(frame.parts)});
  }
  session.replayJournaled(frames);
  report.version = session.snapshot()->version;
  report.frames = frames.size();
  report.meshedOnce = !frames.empty();
  return true;
}

// Frame by frame through the path that served them, each meshed and published; a frame that no
// longer applies ends the replay, and the journal drops it and the later ones.
void replayOneByOne(SceneSession& session, const StoredScene& stored, SceneJournal& journal,
                    RestoredScene& report) {
  for (const SceneJournal::StoredScene::StoredFrame& frame : stored.frames) {
    try {
      const uint64_t reached = session.apply(storedFrame(session, frame.frame)).snapshot->version;
      if (reached != frame.version)
        throw std::runtime_error("replay reached version " + std::to_string(reached));
    } catch (const std::exception& error) {
      report.problem = "frame " + std::to_string(frame.version) + " no longer applies (" +
                       error.what() + "); later frames were dropped";
      journal.truncateAfter(stored.key, report.version);
      return;
    }
    report.version = frame.version;
    ++report.frames;
  }
}

}  // namespace

std::vector<RestoredScene> HttpServer::restore() {
  std::vector<RestoredScene> restored;
  if (!journal_) return restored;
  for (SceneJournal::StoredScene& stored : journal_->load()) {
    const auto start = std::chrono::steady_clock::now();
    RestoredScene report;
    report.id = stored.id;
    std::shared_ptr<SceneSession> session;
    try {
      session = freshSession(stored, options_.engine);
    } catch (const std::exception& error) {  // kept in the journal, not served
      report.served = false;
      report.problem = std::string("not restored: the scene no longer builds (") + error.what() + ")";
      restored.push_back(std::move(report));
      continue;
    }
    report.version = session->snapshot()->version;
    // Frames replay through the same incremental engine path that served them: incremental
    // results match a rebuild only to 1e-9, so replaying is what gives back the served bytes.
    bool done = false;
    try {
      done = replayAtOnce(*session, stored, report);
    } catch (const std::exception& error) {  // e.g. a frame that no longer applies: one by one
      std::fprintf(stderr, "penumbra serve: scene '%s': %s; replaying frame by frame\n",
                   stored.id.c_str(), error.what());
      session = freshSession(stored, options_.engine);
      report.version = session->snapshot()->version;
      report.frames = 0;
      report.meshedOnce = false;
    }
    if (!done) replayOneByOne(*session, stored, *journal_, report);
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::lock_guard lock(scenesMutex_);
    journalKeys_[session.get()] = stored.key;
    scenes_[stored.id] = std::move(session);
    restored.push_back(std::move(report));
  }
  return restored;
}

}  // namespace penumbra::server
