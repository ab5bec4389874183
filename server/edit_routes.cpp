// POST /api/scenes/{id}/edits: one frame of edits, applied whole or refused.
#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <new>
#include <optional>
#include <regex>

#include "core/geom/resource_limit.h"
#include "protocol/edits_json.h"
#include "protocol/frame_result_json.h"
#include "server/body_reader.h"
#include "server/frame_batch.h"
#include "server/frame_cost.h"
#include "server/http_server.h"
#include "server/request_io.h"
#include "server/response_json.h"

namespace penumbra::server {

using nlohmann::json;

namespace {

// "edits[3].transform" → 3 (the edit a frame error is in), or -1.
long editIndexOf(const std::string& path) {
  static const std::regex pattern(R"(^edits\[(\d+)\].*)");
  std::smatch match;
  if (std::regex_match(path, match, pattern)) return std::stol(match[1]);
  return -1;
}

// 507 `out_of_memory` / 500 `frame_not_applied` for a frame that failed after its check.
void sendNotApplied(httplib::Response& res, const SceneSession& session, bool outOfMemory,
                    const std::string& what) {
  const uint64_t version = session.snapshot()->version;
  std::fprintf(stderr, "penumbra serve: scene '%s': frame failed (%s); still at version %llu\n",
               session.id().c_str(), what.c_str(), (unsigned long long)version);
  const std::string message = std::string(outOfMemory ? "out of memory" : "internal error") +
                              " while applying the frame (" + what +
                              "): the frame was not applied; the scene is unchanged at version " +
                              std::to_string(version);
  sendError(
      res,
      ApiError(outOfMemory ? 507 : 500,
               outOfMemory ? error_code::kOutOfMemory : error_code::kFrameNotApplied, "", message),
      {{"applied", false}, {"version", version}});
}

// Who takes turns in a scene's edit queue: the X-Penumbra-Client header, else the
// connection (HTTP/1.1 carries one request at a time per connection).
std::string clientOf(const httplib::Request& req) {
  const std::string named = req.get_header_value("X-Penumbra-Client");
  if (!named.empty() && named.size() <= kMaxIdLength) return "h:" + named;
  return "c:" + req.remote_addr + ":" + std::to_string(req.remote_port);
}

// Counts a waiting edit while it lives.
class WaitingEdit {
 public:
  explicit WaitingEdit(std::atomic<int>& count) : count_(count) {
    admitted_ = ++count_ <= kMaxWaitingEdits;
  }
  ~WaitingEdit() { --count_; }
  WaitingEdit(const WaitingEdit&) = delete;
  WaitingEdit& operator=(const WaitingEdit&) = delete;
  bool admitted() const { return admitted_; }

 private:
  std::atomic<int>& count_;
  bool admitted_ = false;
};

// An add_volume naming another scene's upload (ID-<16 hex digits>.nrrd in the upload folder):
// refused at its key path, since an upload is kept with its own scene (deleted with it, fetched
// with it by the node that serves it next).
void refuseOtherScenesUploads(const Frame& frame, const std::string& sceneId,
                              const std::string& uploadDir) {
  for (size_t e = 0; e < frame.edits.size(); ++e) {
    if (frame.edits[e].op != Edit::Op::AddVolume || uploadDir.empty()) continue;
    const std::filesystem::path file(frame.edits[e].volume.file);
    const std::string name = file.filename().string();
    if (file.parent_path() == uploadDir &&
        (name.size() != sceneId.size() + 1 + 16 + 5 || name.rfind(sceneId + "-", 0) != 0))
      throw protocol::ValidationError("edits[" + std::to_string(e) + "].volume.file",
                                      "names a volume uploaded to another scene; a frame may add "
                                      "only this scene's own uploads");
  }
}

// 200: what the frame (and the frames applied with it, `coalesced_frames` in all) did.
void sendFrameApplied(httplib::Response& res, const SceneSession::Applied& applied, size_t frames) {
  json body = protocol::frameResultToJson(applied.result, applied.snapshot->scene);
  const json delta = changedAtJson(*applied.snapshot, applied.snapshot->version - 1);
  body["mesh_changed"] = delta["changed"];
  body["mesh_removed"] = delta["removed"];
  body["mesh_seconds"] = applied.meshSeconds;
  body["meshed_receivers_count"] = applied.meshedReceivers;
  body["mesh_cells"] = {{"reused", applied.meshCells.cellsReused},
                        {"lit", applied.meshCells.cellsLit},
                        {"chunks_meshed", applied.meshCells.chunksMeshed},
                        {"chunks_kept", applied.meshCells.chunksKept}};
  body["occluder_seconds"] = applied.occluderSeconds;
  body["occluder_receivers_count"] = applied.occluderReceivers;
  body["coalesced_frames"] = frames;
  sendJson(res, 200, body);
}

// A frame waiting in its scene's queue, with the answer it gets (written by whichever thread
// applies its batch; read by its own request thread after EditScheduler::submit returns).
struct QueuedFrame : EditScheduler::Ticket {
  Frame frame;
  std::string body;  // as the client sent it: journaled when applied alone
  httplib::Response* res = nullptr;
};

}  // namespace

void HttpServer::applyFrameAlone(SceneSession& session, EditScheduler::Ticket& ticket) {
  auto& queued = static_cast<QueuedFrame&>(ticket);
  httplib::Response& res = *queued.res;
  SceneSession::Applied applied;
  try {
    // Journaled (committed) before it is published and acknowledged.
    applied = session.apply(
        queued.frame, [&](const SceneSnapshot& next) { journalFrame(session, next, queued.body); });
  } catch (const EditError& error) {
    sendError(res, ApiError(422, error_code::kInvalidFrame, error.keyPath(), error.problem()),
              {{"edit", error.editIndex()}});
    return;
  }
  // Failed inside the engine or while meshing: the session restored the version
  // before the frame (SceneSession::apply), so say plainly that nothing was applied.
  catch (const ResourceLimitError& error) {  // a per-scene budget (EngineSettings::limits)
    sendError(res,
              ApiError(507, error_code::kResourceLimit, "limits." + error.limit(),
                       std::string(error.what()) + ": the frame was not applied"),
              {{"applied", false},
               {"version", session.snapshot()->version},
               {"limit", error.limit()},
               {"maximum", error.maximum()}});
    return;
  } catch (const ApiError& error) {  // the journal could not record it (503)
    sendError(res, error, {{"applied", false}, {"version", session.snapshot()->version}});
    return;
  } catch (const std::bad_alloc&) {
    sendNotApplied(res, session, true, "out of memory");
    return;
  } catch (const std::exception& error) {
    sendNotApplied(res, session, false, error.what());
    return;
  }
  sendFrameApplied(res, applied, 1);
  snapshotIfDue(session, applied.snapshot->version);  // still this scene's turn
}

void HttpServer::applyFrameBatch(SceneSession& session,
                                 const std::vector<EditScheduler::Ticket*>& batch) {
  std::vector<const Frame*> frames;
  for (EditScheduler::Ticket* ticket : batch)
    frames.push_back(&static_cast<QueuedFrame*>(ticket)->frame);
  std::optional<Frame> combined;
  if (batch.size() > 1) combined = combinedFrame(frames);
  if (!combined) {
    for (EditScheduler::Ticket* ticket : batch) applyFrameAlone(session, *ticket);
    return;
  }
  SceneSession::Applied applied;
  try {
    applied = session.apply(*combined, [&](const SceneSnapshot& next) {
      journalFrame(session, next, journaledFrameText(*combined));
    });
  } catch (...) {
    // One frame of the batch is refused (or failed): nothing was applied. Each frame on its
    // own then, so only the bad one fails, with its own edit index.
    for (EditScheduler::Ticket* ticket : batch) applyFrameAlone(session, *ticket);
    return;
  }
  for (EditScheduler::Ticket* ticket : batch)
    sendFrameApplied(*static_cast<QueuedFrame*>(ticket)->res, applied, batch.size());
  snapshotIfDue(session, applied.snapshot->version);  // still this scene's turn
}

void HttpServer::submitFrame(SceneSession& session, Frame frame, const std::string& journaled,
                             const httplib::Request& req, httplib::Response& res) {
  refuseIfStalled(session);  // its kept frames must not be overwritten by new versions
  QueuedFrame queued;
  queued.frame = std::move(frame);
  queued.client = clientOf(req);
  queued.body = journaled;
  queued.res = &res;
  // The answer if the batch's thread failed to give one (it never should).
  sendError(res, ApiError(500, error_code::kFrameNotApplied, "", "no answer from the edit queue"));
  // Wait for this client's turn (round-robin between clients, bounded, frames that
  // queued together applied together: docs/API.md "Load").
  WaitingEdit waiting(waitingEdits_);
  if (!waiting.admitted()) return sendBusy(res, "too many edits waiting on this server");
  try {
    session.editQueue().submit(queued, [&](const std::vector<EditScheduler::Ticket*>& batch) {
      const bool heavy = std::any_of(batch.begin(), batch.end(), [](EditScheduler::Ticket* ticket) {
        return isHeavyFrame(static_cast<QueuedFrame*>(ticket)->frame);
      });
      editWorkers_.run([&] { applyFrameBatch(session, batch); }, heavy);
    });
  } catch (const EditQueueFull&) {
    return sendBusy(res, "too many edits waiting for this scene");
  }
}

void HttpServer::registerEditRoutes() {
  httplib::Server& http = *http_;
  const std::string scenePath = std::string("/api/scenes/") + kIdPattern;

  http.Post(
      scenePath + "/edits",
      readingBody(options_.maxBodyBytes,
                  guarded([this](const httplib::Request& req, httplib::Response& res) {
                    std::shared_ptr<SceneSession> session;
                    try {  // a frame refused before its turn: nothing applied, said as for a failed one
                      session = findScene(req.matches[1]);
                    } catch (const ApiError& error) {
                      sendError(res, error, {{"applied", false}});
                      return;
                    } catch (const JournalUnavailable& error) {
                      sendError(res, journalUnavailableError(error), {{"applied", false}});
                      return;
                    }
                    refuseIfStalled(*session);  // before anything is read: the scene takes no edits
                    const json body = parseBody(req);
                    Frame frame;
                    try {
                      const auto materials = session->snapshot()->scene.materials();
                      // add_volume may name only files the server holds (its uploads, the scene's
                      // own).
                      protocol::VolumeFiles known;
                      known.onlyKnown = true;
                      try {
                        known.knownDirectory = known.baseDirectory = volumeUploadDir();
                      } catch (const std::filesystem::filesystem_error&) {
                        // No upload folder (unwritable): only the scene's own files are known.
                      }
                      known.knownFiles = session->initialVolumeFiles();
                      frame = protocol::frameFromJson(body, &materials, &known);
                      refuseOtherScenesUploads(frame, session->id(), known.knownDirectory);
                    } catch (const protocol::ValidationError& error) {
                      const long edit = editIndexOf(error.path());
                      sendError(
                          res,
                          ApiError(422, error_code::kInvalidFrame, error.path(), error.problem()),
                          edit >= 0 ? json{{"edit", edit}} : json::object());
                      return;
                    }
                    refuseCostlyFrame(estimateFrameCost(session->snapshot()->scene, frame),
                                      options_.maxFrameWork);
                    // A frame adding a volume is journaled with its file resolved (relative to the
                    // data directory when inside it), as a restart reads it.
                    const bool addsVolume =
                        std::any_of(frame.edits.begin(), frame.edits.end(),
                                    [](const Edit& e) { return e.op == Edit::Op::AddVolume; });
                    const std::string journaled = addsVolume ? journaledFrameText(frame) : req.body;
                    submitFrame(*session, std::move(frame), journaled, req, res);
                  })));
}

}  // namespace penumbra::server
