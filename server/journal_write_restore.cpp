// The server's side of the journal (README "Durability"): frames and deletions recorded before
// they are acknowledged, and every journaled scene brought back at start. (A frame that fails
// mid-apply is undone by the engine rollback, scene_session_rollback.cpp, not here.)
#include <algorithm>
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
#include "server/journal_unavailable.h"
#include "server/journaled_text.h"
#include "server/orphan_uploads.h"
#include "server/part_changes.h"
#include "server/stored_parts.h"

namespace penumbra::server {

namespace {

ApiError journalError(const std::string& what, const std::exception& error) {
  return ApiError(
      503, error_code::kJournalFailed, "",
      "the journal could not record " + what + " (" + error.what() + "); nothing was acknowledged");
}

}  // namespace

int64_t HttpServer::journalKeyOf(const SceneSession& session) const {
  {
    std::lock_guard lock(scenesMutex_);
    const auto it = journalKeys_.find(&session);
    if (it != journalKeys_.end()) return it->second;
  }
  // Dropped since the request found it (its lease lost or handed over: still journaled), or
  // deleted.
  if (leases_ && journal_->hasScene(session.id()))
    throw ApiError(503, error_code::kOwnedElsewhere, "id",
                   "scene '" + session.id() +
                       "' is no longer served by this node; nothing was applied, retry");
  throw ApiError(404, error_code::kNotFound, "id", "the scene was deleted");
}

void HttpServer::journalFrame(const SceneSession& session, const SceneSnapshot& next,
                              const std::string& frame) {
  if (!journal_) return;
  int64_t key = -1;
  try {
    key = journalKeyOf(session);  // asks the journal when the scene was dropped meanwhile
  } catch (const JournalUnavailable& error) {
    throw journalError("the frame; it was not applied", error);
  }
  try {
    journal_->addFrame(key, next.version, frame, partChangesText(partChangesOf(next)),
                       next.frameBase);
  } catch (const LeaseLost& error) {
    // Another node took the scene over: this one stops serving it (the frame is undone, its
    // streams end) and the client's retry finds the new owner.
    dropScene(session.id(), error.what());
    throw ApiError(503, error_code::kOwnedElsewhere, "id",
                   std::string(error.what()) + "; the frame was not applied, retry");
  } catch (const std::exception& error) {
    // Nothing is published and SceneSession::apply undoes the frame in the engine (atomic
    // frames): the scene stays at its last acknowledged version and the frame may be sent again.
    throw journalError("the frame; it was not applied", error);
  }
}

std::string HttpServer::journaledFrameText(const Frame& frame) const {
  nlohmann::json text = protocol::frameToJson(frame);
  if (!journal_) return text.dump();
  for (nlohmann::json& edit : text["edits"])
    if (edit.value("op", "") == "add_volume")
      relativeToDataDir(edit["volume"]["file"], journal_->directory());
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
  nlohmann::json snapshotProblems = nlohmann::json::array();
  {
    std::lock_guard lock(scenesMutex_);
    for (const JournalProblem& problem : journalProblems_)
      problems.push_back(
          {{"id", problem.id},
           {"stalled_at", problem.stalledAt ? nlohmann::json(*problem.stalledAt) : nullptr},
           {"served", problem.stalledAt.has_value()},
           {"problem", problem.problem}});
    for (const auto& [id, problem] : snapshotProblems_)
      snapshotProblems.push_back({{"id", id}, {"problem", problem}});
  }
  const std::string durability = journal_->durabilityProblem();
  return {{"path", journal_->path()},
          {"integrity", journal_->integrity()},
          {"read", journal_->loadProblem().empty() ? "ok" : journal_->loadProblem()},
          {"durability", durability.empty() ? "ok" : durability},
          {"scene_problems", std::move(problems)},
          {"snapshot_every", options_.snapshotEvery},
          {"snapshot_problems", std::move(snapshotProblems)},
          {"node", leases_ ? nlohmann::json(leases_->node()) : nlohmann::json(nullptr)}};
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
  } catch (const LeaseLost& error) {
    dropScene(session.id(), error.what());
    throw ApiError(503, error_code::kOwnedElsewhere, "id",
                   std::string(error.what()) + "; the scene was not deleted, retry");
  } catch (const std::exception& error) {
    throw journalError("the deletion", error);
  }
  std::lock_guard lock(scenesMutex_);
  if (const auto lease = leaseTokens_.find(session.id()); lease != leaseTokens_.end()) {
    leases_->releaseOrLetExpire(session.id(), lease->second);
    leaseTokens_.erase(lease);
    lastUse_.erase(session.id());
  }
  journalKeys_.erase(&session);
  stalls_.erase(&session);  // deleted by its user: its kept frames went with it
  std::erase_if(journalProblems_, [&](const JournalProblem& p) { return p.id == session.id(); });
}

namespace {

using StoredScene = SceneJournal::StoredScene;
using StoredFrame = SceneJournal::StoredScene::StoredFrame;

Frame storedFrame(const SceneSession& session, const SceneJournal& journal,
                  const std::string& text) {
  const auto materials = session.snapshot()->scene.materials();  // edits change no material
  const protocol::VolumeFiles volumeFiles = journaledFiles(journal.directory());
  return protocol::frameFromJson(
      protocol::parseJsonText(text, text.size(), protocol::kMaxJsonDepth), &materials,
      &volumeFiles);
}

// The frames after version `after` up to the first one whose checksum fails (all of them when
// none fails); `problem` says which failed.
std::vector<StoredFrame> intactTail(const StoredScene& stored, uint64_t after,
                                    std::string& problem) {
  std::vector<StoredFrame> frames;
  for (const StoredFrame& frame : stored.frames) {
    if (frame.version <= after) continue;
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
                  const std::vector<StoredFrame>& stored, RestoredScene& report,
                  const EngineProgress& progress) {
  std::vector<SceneSession::JournaledFrame> frames;
  for (const StoredFrame& frame : stored) {
    if (frame.parts.empty()) return false;
    frames.push_back({storedFrame(session, journal, frame.frame), frame.version,
                      partChangesFromText(frame.parts), frame.base});
  }
  session.replayJournaled(
      frames, [&](const Scene& scene) { return journaledScene(scene, journal.directory()); },
      progress);
  report.version = session.snapshot()->version;
  report.frames = frames.size();
  report.meshedOnce = !frames.empty();
  return true;
}

// Frame by frame through the path that served them, each meshed and published; a frame that no
// longer applies ends the replay there (`problem`). The journal is not touched. A cancel
// (`progress` throws BuildCancelled, checked before each frame) ends it.
void replayOneByOne(SceneSession& session, const SceneJournal& journal,
                    const std::vector<StoredFrame>& stored, RestoredScene& report,
                    std::string& problem, const EngineProgress& progress) {
  for (const StoredFrame& frame : stored) {
    if (progress) progress("replaying", report.frames, stored.size());
    try {
      if (frame.base && *frame.base > session.engineBase()) {  // served on a fresh build here
        if (*frame.base != report.version)
          throw std::runtime_error("it was applied on a build of version " +
                                   std::to_string(*frame.base));
        session.rebase(
            [&](const Scene& scene) { return journaledScene(scene, journal.directory()); },
            progress);
      }
      const uint64_t reached =
          session.apply(storedFrame(session, journal, frame.frame)).snapshot->version;
      if (reached != frame.version)
        throw std::runtime_error("replay reached version " + std::to_string(reached));
    } catch (const BuildCancelled&) {
      throw;
    } catch (const std::exception& error) {
      problem =
          "frame " + std::to_string(frame.version) + " no longer applies (" + error.what() + ")";
      return;
    }
    report.version = frame.version;
    ++report.frames;
  }
}

using StoredSnapshot = SceneJournal::StoredScene::StoredSnapshot;

// The session a restore starts from: a build of the snapshot's scene serving its stored parts,
// or (no snapshot) of the scene's source at its first version. Throws when it does not load.
std::shared_ptr<SceneSession> startSession(const StoredScene& stored, const StoredSnapshot* from,
                                           const SceneJournal& journal,
                                           const EngineSettings& settings,
                                           const EngineProgress& progress) {
  if (!from)
    return std::make_shared<SceneSession>(
        stored.id, stored.name, sceneFromJournaledText(stored.source, journal.directory()),
        settings, progress);
  StoredParts parts = decodeStoredParts(from->parts);  // cheap checks before the build
  Scene scene = sceneFromJournaledText(from->source, journal.directory());
  scene.setHandles(std::move(parts.handles), parts.nextHandle);
  auto session =
      std::make_shared<SceneSession>(stored.id, stored.name, std::move(scene), settings, progress);
  session->adoptSnapshot(from->version, std::move(parts));
  return session;
}

// The newest snapshot that verifies and loads, its session in `session`; null (and `session`
// untouched) when none does. What was passed over is said in report.snapshotProblem.
const StoredSnapshot* newestSnapshot(const StoredScene& stored, const SceneJournal& journal,
                                     const EngineSettings& settings,
                                     std::shared_ptr<SceneSession>& session,
                                     RestoredScene& report, const EngineProgress& progress) {
  auto note = [&](const std::string& what) {
    report.snapshotProblem += (report.snapshotProblem.empty() ? "" : "; ") + what;
  };
  for (auto it = stored.snapshots.rbegin(); it != stored.snapshots.rend(); ++it) {
    const std::string name = "the snapshot at version " + std::to_string(it->version);
    if (!it->intact) {
      note(name + " fails its checksum (damaged in the journal)");
      continue;
    }
    try {
      session = startSession(stored, &*it, journal, settings, progress);
    } catch (const BuildCancelled&) {
      throw;
    } catch (const std::exception& error) {
      note(name + " does not load (" + error.what() + ")");
      continue;
    }
    for (const StoredFrame& frame : stored.frames)  // covered, yet damage is said
      if (frame.version <= it->version && !frame.intact)
        note("frame " + std::to_string(frame.version) + " fails its checksum (" + name +
             " covers it)");
    if (!report.snapshotProblem.empty()) note("restored from " + name);
    return &*it;
  }
  if (!report.snapshotProblem.empty()) note("restored by replaying every frame");
  return nullptr;
}

// Brings one journaled scene back as far as its frames allow: from its newest snapshot that
// verifies and loads, else from its source, then the frames after it. Null when neither builds
// (kept in the journal, not served). Sets report.stalledAt when it stops short, or when
// `volumeProblem` says its uploaded volumes could not all be put in place. BuildCancelled from
// `progress` (a cancel) ends it, whatever it was doing: the caller drops what it built.
std::shared_ptr<SceneSession> restoreScene(const StoredScene& stored, const SceneJournal& journal,
                                           const EngineSettings& settings,
                                           const std::string& volumeProblem,
                                           RestoredScene& report, const EngineProgress& progress) {
  std::shared_ptr<SceneSession> session;
  const StoredSnapshot* from = newestSnapshot(stored, journal, settings, session, report, progress);
  if (from) {
    report.snapshot = from->version;
  } else if (!stored.sourceIntact) {
    report.served = false;
    report.problem = "not restored: the scene's source fails its checksum (damaged in the journal)";
    return nullptr;
  } else {
    try {
      session = startSession(stored, nullptr, journal, settings, progress);
    } catch (const BuildCancelled&) {
      throw;
    } catch (const std::exception& error) {  // kept in the journal, not served
      report.served = false;
      report.problem = std::string("not restored: the scene no longer builds (") + error.what() +
                       ")" + (volumeProblem.empty() ? "" : "; " + volumeProblem);
      return nullptr;
    }
  }
  report.version = session->snapshot()->version;
  std::string problem;
  const std::vector<StoredFrame> frames = intactTail(stored, report.version, problem);
  // Frames replay through the same incremental engine path that served them, on the same fresh
  // builds: incremental results match a rebuild only to 1e-9, so this is what gives back the
  // served bytes.
  bool done = false;
  try {
    done = replayAtOnce(*session, journal, frames, report, progress);
  } catch (const BuildCancelled&) {
    throw;
  } catch (const std::exception& error) {  // e.g. a frame that no longer applies: one by one
    std::fprintf(stderr, "penumbra serve: scene '%s': %s; replaying frame by frame\n",
                 stored.id.c_str(), error.what());
    session.reset();  // its memory before the next build
    session = startSession(stored, from, journal, settings, progress);
    report.version = session->snapshot()->version;
    report.frames = 0;
    report.meshedOnce = false;
  }
  if (!done) replayOneByOne(*session, journal, frames, report, problem, progress);
  if (problem.empty() && !stored.complete) problem = "the journal could not be read to its end";
  if (!volumeProblem.empty())
    problem = problem.empty() ? volumeProblem : problem + " (" + volumeProblem + ")";
  if (problem.empty() && !journal.logDamage().empty())
    problem = "the journal lost committed frames (" + journal.logDamage() + ")";
  if (!problem.empty()) {
    report.stalledAt = report.version;
    const size_t kept = size_t(
        std::count_if(stored.frames.begin(), stored.frames.end(),
                      [&](const StoredFrame& frame) { return frame.version > report.version; }));
    report.problem = problem + "; stalled at version " + std::to_string(report.version) + ", " +
                     std::to_string(kept) + " later frame" + (kept == 1 ? "" : "s") +
                     " kept in the journal; edits are refused until it is repaired";
  }
  return session;
}

}  // namespace

void HttpServer::reserveJournalScenes() {
  if (!journal_ || pendingRestore_) return;
  if (leases_ && !options_.restoreAtStart) {  // a node among several: scenes come on request
    pendingRestore_.emplace();
    return;
  }
  pendingRestore_ = journal_->load();
  if (leases_) takeLeasesOf(*pendingRestore_);
  if (!options_.dataDir.empty() && !leases_) {
    const std::string uploads = (std::filesystem::path(options_.dataDir) / "volumes").string();
    if (const size_t removed = removeOrphanUploads(uploads, *pendingRestore_))
      std::fprintf(stderr,
                   "penumbra serve: removed %zu uploaded volume file(s) no journaled frame names (stored, then the "
                   "server stopped before their frame was acknowledged)\n",
                   removed);
  }
  std::lock_guard lock(scenesMutex_);
  for (const SceneJournal::StoredScene& stored : *pendingRestore_)
    if (scenes_.emplace(stored.id, nullptr).second) {
      auto job = std::make_shared<RestoreJob>(stored.id);
      if (stopping_) job->cancel();
      restoring_.emplace(stored.id, std::move(job));
    }
}

std::vector<RestoredScene> HttpServer::restore() {
  std::vector<RestoredScene> restored;
  if (!journal_) return restored;
  if (!pendingRestore_) reserveJournalScenes();
  std::vector<SceneJournal::StoredScene> journaled = std::move(*pendingRestore_);
  pendingRestore_.reset();
  for (SceneJournal::StoredScene& stored : journaled) {
    std::shared_ptr<RestoreJob> job;
    {
      std::lock_guard lock(scenesMutex_);
      if (const auto it = restoring_.find(stored.id); it != restoring_.end()) job = it->second;
    }
    const bool reserved = job != nullptr;  // else the id was taken already (a scene served twice)
    if (!reserved) job = std::make_shared<RestoreJob>(stored.id);
    RestoredScene report;
    std::shared_ptr<SceneSession> session;
    try {
      session = restoreStored(stored, report, *job);
    } catch (const BuildCancelled&) {  // a DELETE of the scene, or a stop
      session.reset();  // its memory first
      const RestoreJob::Ended ended = dropCancelledRestore(stored.id, stored.key, *job);
      report.served = false;
      report.problem = ended.deleted ? "deleted while it was being restored"
                       : job->deleteWanted()
                           ? "deleted while it was being restored, but the journal could not "
                             "remove it (" + ended.problem + "); it comes back at the next start"
                           : "not restored: the server is stopping (the journal is unchanged)";
      {
        std::lock_guard lock(scenesMutex_);
        if (reserved) {
          restoring_.erase(stored.id);
          scenes_.erase(stored.id);
        }
      }
      job->end(ended);
      restored.push_back(std::move(report));
      continue;
    } catch (...) {
      job->end({});
      throw;
    }
    bool served = false;
    {
      std::lock_guard lock(scenesMutex_);
      if (reserved && restoring_.erase(stored.id)) {
        if (session) {
          served = true;
          journalKeys_[session.get()] = stored.key;
          if (report.stalledAt) stalls_[session.get()] = SceneStall{*report.stalledAt, report.problem};
          if (leases_) lastUse_[stored.id] = std::chrono::steady_clock::now();
          scenes_[stored.id] = std::move(session);
        } else {
          scenes_.erase(stored.id);  // not served: the id is free
        }
      }
    }
    job->end({served, false, ""});
    restored.push_back(std::move(report));
  }
  return restored;
}

std::shared_ptr<SceneSession> HttpServer::restoreStored(const SceneJournal::StoredScene& stored,
                                                        RestoredScene& report, RestoreJob& job) {
  const auto start = std::chrono::steady_clock::now();
  report.id = stored.id;
  const EngineProgress progress = job.progress();
  progress("restoring", 0, 0);  // a restore cancelled before it began goes no further
  // Its uploads first: a node restoring a scene another node served fetches them.
  const std::string volumeProblem = journal_->fetchVolumes(stored);
  std::shared_ptr<SceneSession> session =
      restoreScene(stored, *journal_, options_.engine, volumeProblem, report, progress);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::lock_guard lock(scenesMutex_);
  if (!report.problem.empty())
    journalProblems_.push_back({report.id, report.stalledAt, report.problem});
  if (!report.snapshotProblem.empty()) {  // loud, though the scene came back whole
    std::fprintf(stderr, "penumbra serve: scene '%s': %s\n", report.id.c_str(),
                 report.snapshotProblem.c_str());
    snapshotProblems_.push_back({report.id, report.snapshotProblem});
  }
  return session;
}

std::optional<SceneStall> HttpServer::stallOf(const SceneSession& session) const {
  std::lock_guard lock(scenesMutex_);
  const auto it = stalls_.find(&session);
  if (it == stalls_.end()) return std::nullopt;
  return it->second;
}

}  // namespace penumbra::server
