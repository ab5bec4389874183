// The server's side of the journal (README "Durability"): frames and deletions recorded before
// they are acknowledged, and every journaled scene brought back at start.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>

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
  return ApiError(
      503, error_code::kJournalFailed, "",
      "the journal could not record " + what + " (" + error.what() + "); nothing was acknowledged");
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

std::string HttpServer::journaledFrameText(const Frame& frame) const {
  nlohmann::json text = protocol::frameToJson(frame);
  if (!journal_) return text.dump();
  const std::filesystem::path dir(journal_->directory());
  for (nlohmann::json& edit : text["edits"]) {
    if (edit.value("op", "") != "add_volume") continue;
    nlohmann::json& file = edit["volume"]["file"];
    const std::filesystem::path relative =
        std::filesystem::path(file.get<std::string>()).lexically_relative(dir);
    if (!relative.empty() && *relative.begin() != "..") file = relative.string();
  }
  return text.dump();
}

void HttpServer::refuseIfStalled(const SceneSession& session) const {
  if (const auto stall = stallOf(session))
    throw ApiError(409, error_code::kSceneStalled, "id",
                   "scene '" + session.id() + "' is stalled at version " +
                       std::to_string(stall->version) + " and takes no edits: " + stall->problem);
}

void HttpServer::refuseIfNotDurable() const {
  if (!journal_) return;
  if (const std::string problem = journal_->durabilityProblem(); !problem.empty())
    throw ApiError(
        503, error_code::kJournalFailed, "",
        "the journal cannot record anything durably (" + problem + "); nothing was acknowledged");
}

nlohmann::json HttpServer::journalHealthJson() const {
  if (!journal_) return nullptr;
  nlohmann::json problems = nlohmann::json::array();
  {
    std::lock_guard lock(scenesMutex_);
    for (const JournalProblem& problem : journalProblems_)
      problems.push_back(
          {{"id", problem.id},
           {"stalled_at", problem.stalledAt ? nlohmann::json(*problem.stalledAt) : nullptr},
           {"served", problem.stalledAt.has_value()},
           {"problem", problem.problem}});
  }
  const std::string durability = journal_->durabilityProblem();
  return {{"path", journal_->path()},
          {"integrity", journal_->integrity()},
          {"read", journal_->loadProblem().empty() ? "ok" : journal_->loadProblem()},
          {"durability", durability.empty() ? "ok" : durability},
          {"scene_problems", std::move(problems)}};
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
  stalls_.erase(&session);  // deleted by its user: its kept frames went with it
  std::erase_if(journalProblems_, [&](const JournalProblem& p) { return p.id == session.id(); });
}

namespace {

using StoredScene = SceneJournal::StoredScene;
using StoredFrame = SceneJournal::StoredScene::StoredFrame;

// Files the journal names: uploads as paths relative to the data directory (so the directory
// may move), older journals' absolute paths as they are.
protocol::VolumeFiles journaledFiles(const SceneJournal& journal) {
  protocol::VolumeFiles files;
  files.baseDirectory = journal.directory();
  return files;
}

std::shared_ptr<SceneSession> freshSession(const StoredScene& stored, const SceneJournal& journal,
                                           const EngineSettings& settings) {
  // Only scene files loaded by the operator and the server's own uploads can hold volumes:
  // reading them again is safe.
  const protocol::VolumeFiles volumeFiles = journaledFiles(journal);
  return std::make_shared<SceneSession>(
      stored.id, stored.name,
      protocol::sceneFromJson(
          protocol::parseJsonText(stored.source, stored.source.size(), protocol::kMaxJsonDepth),
          &volumeFiles),
      settings);
}

Frame storedFrame(const SceneSession& session, const SceneJournal& journal,
                  const std::string& text) {
  const auto materials = session.snapshot()->scene.materials();  // edits change no material
  const protocol::VolumeFiles volumeFiles = journaledFiles(journal);
  return protocol::frameFromJson(
      protocol::parseJsonText(text, text.size(), protocol::kMaxJsonDepth), &materials,
      &volumeFiles);
}

// The frames before the first one whose checksum fails (all of them when none fails);
// `problem` says which failed.
std::vector<StoredFrame> intactPrefix(const StoredScene& stored, std::string& problem) {
  std::vector<StoredFrame> frames;
  for (const StoredFrame& frame : stored.frames) {
    if (!frame.intact) {
      problem =
          "frame " + std::to_string(frame.version) + " fails its checksum (damaged in the journal)";
      break;
    }
    frames.push_back(frame);
  }
  return frames;
}

// Every frame through the engine, meshed once at the end (SceneSession::replayJournaled):
// possible when each frame's part changes were journaled (journals before them: no).
bool replayAtOnce(SceneSession& session, const SceneJournal& journal,
                  const std::vector<StoredFrame>& stored, RestoredScene& report) {
  std::vector<SceneSession::JournaledFrame> frames;
  for (const StoredFrame& frame : stored) {
    if (frame.parts.empty()) return false;
    frames.push_back({storedFrame(session, journal, frame.frame), frame.version,
                      partChangesFromText(frame.parts)});
  }
  session.replayJournaled(frames);
  report.version = session.snapshot()->version;
  report.frames = frames.size();
  report.meshedOnce = !frames.empty();
  return true;
}

// Frame by frame through the path that served them, each meshed and published; a frame that no
// longer applies ends the replay there (`problem`). The journal is not touched.
void replayOneByOne(SceneSession& session, const SceneJournal& journal,
                    const std::vector<StoredFrame>& stored, RestoredScene& report,
                    std::string& problem) {
  for (const StoredFrame& frame : stored) {
    try {
      const uint64_t reached =
          session.apply(storedFrame(session, journal, frame.frame)).snapshot->version;
      if (reached != frame.version)
        throw std::runtime_error("replay reached version " + std::to_string(reached));
    } catch (const std::exception& error) {
      problem =
          "frame " + std::to_string(frame.version) + " no longer applies (" + error.what() + ")";
      return;
    }
    report.version = frame.version;
    ++report.frames;
  }
}

// Brings one journaled scene back as far as its frames allow; null when its source does not
// build (kept in the journal, not served). Sets report.stalledAt when it stops short.
std::shared_ptr<SceneSession> restoreScene(const StoredScene& stored, const SceneJournal& journal,
                                           const EngineSettings& settings, RestoredScene& report) {
  if (!stored.sourceIntact) {
    report.served = false;
    report.problem = "not restored: the scene's source fails its checksum (damaged in the journal)";
    return nullptr;
  }
  std::shared_ptr<SceneSession> session;
  try {
    session = freshSession(stored, journal, settings);
  } catch (const std::exception& error) {  // kept in the journal, not served
    report.served = false;
    report.problem = std::string("not restored: the scene no longer builds (") + error.what() + ")";
    return nullptr;
  }
  report.version = session->snapshot()->version;
  std::string problem;
  const std::vector<StoredFrame> frames = intactPrefix(stored, problem);
  // Frames replay through the same incremental engine path that served them: incremental
  // results match a rebuild only to 1e-9, so replaying is what gives back the served bytes.
  bool done = false;
  try {
    done = replayAtOnce(*session, journal, frames, report);
  } catch (const std::exception& error) {  // e.g. a frame that no longer applies: one by one
    std::fprintf(stderr, "penumbra serve: scene '%s': %s; replaying frame by frame\n",
                 stored.id.c_str(), error.what());
    session = freshSession(stored, journal, settings);
    report.version = session->snapshot()->version;
    report.frames = 0;
    report.meshedOnce = false;
  }
  if (!done) replayOneByOne(*session, journal, frames, report, problem);
  if (problem.empty() && !stored.complete) problem = "the journal could not be read to its end";
  if (problem.empty() && !journal.logDamage().empty())
    problem = "the journal lost committed frames (" + journal.logDamage() + ")";
  if (!problem.empty()) {
    report.stalledAt = report.version;
    const size_t kept = stored.frames.size() - report.frames;
    report.problem = problem + "; stalled at version " + std::to_string(report.version) + ", " +
                     std::to_string(kept) + " later frame" + (kept == 1 ? "" : "s") +
                     " kept in the journal; edits are refused until it is repaired";
  }
  return session;
}

}  // namespace

void HttpServer::reserveJournalScenes() {
  if (!journal_ || pendingRestore_) return;
  pendingRestore_ = journal_->load();
  std::lock_guard lock(scenesMutex_);
  for (const SceneJournal::StoredScene& stored : *pendingRestore_)
    if (scenes_.emplace(stored.id, nullptr).second) restoring_.insert(stored.id);
}

std::vector<RestoredScene> HttpServer::restore() {
  std::vector<RestoredScene> restored;
  if (!journal_) return restored;
  if (!pendingRestore_) reserveJournalScenes();
  std::vector<SceneJournal::StoredScene> journaled = std::move(*pendingRestore_);
  pendingRestore_.reset();
  for (SceneJournal::StoredScene& stored : journaled) {
    const auto start = std::chrono::steady_clock::now();
    RestoredScene report;
    report.id = stored.id;
    std::shared_ptr<SceneSession> session =
        restoreScene(stored, *journal_, options_.engine, report);
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::lock_guard lock(scenesMutex_);
    if (!report.problem.empty())
      journalProblems_.push_back({report.id, report.stalledAt, report.problem});
    if (restoring_.erase(stored.id) == 0) {
      restored.push_back(std::move(report));  // the id was taken already (a scene served twice)
      continue;
    }
    if (session) {
      journalKeys_[session.get()] = stored.key;
      if (report.stalledAt) stalls_[session.get()] = SceneStall{*report.stalledAt, report.problem};
      scenes_[stored.id] = std::move(session);
    } else {
      scenes_.erase(stored.id);  // not served: the id is free
    }
    restored.push_back(std::move(report));
  }
  return restored;
}

std::optional<SceneStall> HttpServer::stallOf(const SceneSession& session) const {
  std::lock_guard lock(scenesMutex_);
  const auto it = stalls_.find(&session);
  if (it == stalls_.end()) return std::nullopt;
  return it->second;
}

}  // namespace penumbra::server
