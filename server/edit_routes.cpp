// POST /api/scenes/{id}/edits: one frame of edits, applied whole or refused.
#include "server/http_server.h"

#include <httplib.h>

#include <cstdio>
#include <new>
#include <atomic>
#include <optional>
#include <regex>

#include "core/geom/resource_limit.h"
#include "protocol/edits_json.h"
#include "protocol/frame_result_json.h"
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
  sendError(res,
            ApiError(outOfMemory ? 507 : 500,
                     outOfMemory ? error_code::kOutOfMemory : error_code::kFrameNotApplied, "",
                     message),
            {{"applied", false}, {"version", version}});
}


// Who takes turns in a scene's edit queue: the X-Penumbra-Client header, else the
// connection (HTTP/1.1 carries one request at a time per connection).
std::string clientOf(const httplib::Request& req) {
  const std::string named = req.get_header_value("X-Penumbra-Client");
  if (!named.empty() && named.size() <= kMaxIdLength) return "h:" + named;
  return "c:" + req.remote_addr + ":" + std::to_string(req.remote_port);
}

void sendBusy(httplib::Response& res, const std::string& why) {
  sendError(res, ApiError(503, error_code::kBusy, "", why + "; retry after 1 s"));
  res.set_header("Retry-After", "1");
}

// Counts a waiting edit while it lives.
class WaitingEdit {
 public:
  explicit WaitingEdit(std::atomic<int>& count) : count_(count) { admitted_ = ++count_ <= kMaxWaitingEdits; }
  ~WaitingEdit() { --count_; }
  WaitingEdit(const WaitingEdit&) = delete;
  WaitingEdit& operator=(const WaitingEdit&) = delete;
  bool admitted() const { return admitted_; }

 private:
  std::atomic<int>& count_;
  bool admitted_ = false;
};

}  // namespace

void HttpServer::registerEditRoutes() {
  httplib::Server& http = *http_;
  const std::string scenePath = std::string("/api/scenes/") + kIdPattern;

  http.Post(
      scenePath + "/edits", guarded([this](const httplib::Request& req, httplib::Response& res) {
        const auto session = findScene(req.matches[1]);
        const json body = parseBody(req);
        Frame frame;
        try {
          const auto materials = session->snapshot()->scene.materials();
          frame = protocol::frameFromJson(body, &materials);
        } catch (const protocol::ValidationError& error) {
          const long edit = editIndexOf(error.path());
          sendError(res, ApiError(422, error_code::kInvalidFrame, error.path(), error.problem()),
                    edit >= 0 ? json{{"edit", edit}} : json::object());
          return;
        }
        // Wait for this client's turn (round-robin between clients, bounded: docs/API.md "Load").
        std::optional<EditScheduler::Turn> turn;
        {
          WaitingEdit waiting(waitingEdits_);
          if (!waiting.admitted()) return sendBusy(res, "too many edits waiting on this server");
          try {
            turn.emplace(session->editQueue().wait(clientOf(req)));
          } catch (const EditQueueFull&) {
            return sendBusy(res, "too many edits waiting for this scene");
          }
        }
        SceneSession::Applied applied;
        try {
          // Journaled (committed) before it is published and acknowledged.
          applied = session->apply(frame, [&](const SceneSnapshot& next) {
            journalFrame(*session, next.version, req.body);
          });
          turn.reset();  // the next client's frame applies while this answer is written
        } catch (const EditError& error) {
          const std::string path = "edits[" + std::to_string(error.editIndex()) + "]" +
                                   (error.path().empty() ? "" : "." + error.path());
          std::string problem = error.what();
          if (const size_t colon = problem.find(": "); colon != std::string::npos)
            problem = problem.substr(colon + 2);
          sendError(res, ApiError(422, error_code::kInvalidFrame, path, problem),
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
                     {"version", session->snapshot()->version},
                     {"limit", error.limit()},
                     {"maximum", error.maximum()}});
          return;
        } catch (const ApiError& error) {  // the journal could not record it (503)
          sendError(res, error, {{"applied", false}, {"version", session->snapshot()->version}});
          return;
        } catch (const std::bad_alloc&) {
          sendNotApplied(res, *session, true, "out of memory");
          return;
        } catch (const std::exception& error) {
          sendNotApplied(res, *session, false, error.what());
          return;
        }
        json body200 = protocol::frameResultToJson(applied.result, applied.snapshot->scene);
        const json delta = changedAtJson(*applied.snapshot, applied.snapshot->version - 1);
        body200["mesh_changed"] = delta["changed"];
        body200["mesh_removed"] = delta["removed"];
        body200["mesh_seconds"] = applied.meshSeconds;
        body200["meshed_receivers_count"] = applied.meshedReceivers;
        body200["mesh_cells"] = {{"reused", applied.meshCells.cellsReused},
                                 {"lit", applied.meshCells.cellsLit},
                                 {"chunks_meshed", applied.meshCells.chunksMeshed},
                                 {"chunks_kept", applied.meshCells.chunksKept}};
        sendJson(res, 200, body200);
      }));
}

}  // namespace penumbra::server
