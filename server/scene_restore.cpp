// The server's side of the journal (README "Durability"): frames and deletions recorded before
// they are acknowledged, and every journaled scene brought back at start.
#include <chrono>

#include "protocol/edits_json.h"
#include "protocol/json_text.h"
#include "protocol/scene_json.h"
#include "server/api_errors.h"
#include "server/http_server.h"

namespace penumbra::server {

namespace {

ApiError journalError(const std::string& what, const std::exception& error) {
  return ApiError(503, error_code::kJournalFailed, "",
                  "the journal could not record " + what + " (" + error.what() +
                      "); nothing was acknowledged");
}

}  // namespace

void HttpServer::journalFrame(const SceneSession& session, uint64_t version,
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
    journal_->addFrame(key, version, frame);
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

std::vector<RestoredScene> HttpServer::restore() {
  std::vector<RestoredScene> restored;
  if (!journal_) return restored;
  for (SceneJournal::StoredScene& stored : journal_->load()) {
    const auto start = std::chrono::steady_clock::now();
    RestoredScene report;
    report.id = stored.id;
    std::shared_ptr<SceneSession> session;
    try {
      session = std::make_shared<SceneSession>(
          stored.id, stored.name,
          protocol::sceneFromJson(protocol::parseJsonText(stored.source, stored.source.size(),
                                                          protocol::kMaxJsonDepth)),
          options_.engine);
    } catch (const std::exception& error) {  // kept in the journal, not served
      report.served = false;
      report.problem = std::string("not restored: the scene no longer builds (") + error.what() + ")";
      restored.push_back(std::move(report));
      continue;
    }
    report.version = session->snapshot()->version;
    // Frames replay through the same incremental path that served them: incremental results
    // match a rebuild only to 1e-9, so replaying is what gives back the served bytes.
    for (const auto& [version, text] : stored.frames) {
      try {
        const auto materials = session->snapshot()->scene.materials();
        const Frame frame = protocol::frameFromJson(
            protocol::parseJsonText(text, text.size(), protocol::kMaxJsonDepth), &materials);
        const uint64_t reached = session->apply(frame).snapshot->version;
        if (reached != version)
          throw std::runtime_error("replay reached version " + std::to_string(reached));
      } catch (const std::exception& error) {
        report.problem = "frame " + std::to_string(version) + " no longer applies (" +
                         error.what() + "); later frames were dropped";
        journal_->truncateAfter(stored.key, report.version);
        break;
      }
      report.version = version;
      ++report.frames;
    }
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
