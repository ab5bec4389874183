// Scenes as resources: health, list, create (JSON or an imported file), get, delete,
// rebuild, stats.
#include <httplib.h>

#include <algorithm>
#include <cctype>
#include <chrono>

#include "core/geom/resource_limit.h"
#include "interchange/scene_import.h"
#include "protocol/build_stats_json.h"
#include "protocol/frame_result_json.h"
#include "protocol/scene_json.h"
#include "server/body_reader.h"
#include "server/http_server.h"
#include "server/request_io.h"
#include "server/response_json.h"
#include "server/scene_upload.h"
#include "server/utf8_boundary.h"

namespace penumbra::server {

using nlohmann::json;

namespace {

using Clock = std::chrono::steady_clock;

constexpr size_t kMaxTicketLength = 64;

// ?ticket=T: the creating client's label for its build, shown in the scene list while it builds.
std::string ticketOf(const httplib::Request& req) {
  const std::string ticket = queryText(req, "ticket").value_or("");
  const bool wellFormed =
      ticket.size() <= kMaxTicketLength &&
      std::all_of(ticket.begin(), ticket.end(), [](unsigned char c) {
        return std::isalnum(c) || c == '_' || c == '-';
      });
  if (!wellFormed)
    throw ApiError(400, error_code::kBadParameter, "query.ticket",
                   "ticket must be at most 64 letters, digits, '_' or '-'");
  return ticket;
}

}  // namespace

void HttpServer::registerSceneRoutes() {
  httplib::Server& http = *http_;
  const std::string scenePath = std::string("/api/scenes/") + kIdPattern;

  http.Get("/api/health", guarded([this](const httplib::Request&, httplib::Response& res) {
             size_t scenes = 0, restoring = 0, building = 0;
             {
               std::lock_guard lock(scenesMutex_);
               scenes = scenes_.size();
               restoring = restoring_.size();
               building = builds_.size();
             }
             // Durable: a journal whose directory is still the one locked and writable; any
             // damage or stalled scene found at start makes the status "degraded".
             json journal = journalHealthJson();
             const bool durable = journal_ && journal["durability"] == "ok";
             const bool degraded =
                 journal_ &&
                 (!durable || journal["integrity"] != "ok" || journal["read"] != "ok" ||
                  !journal["scene_problems"].empty() || !journal["snapshot_problems"].empty());
             sendJson(res, 200,
                      {{"status", degraded ? "degraded" : "ok"},
                       {"scenes", scenes},
                       {"restoring", restoring},
                       {"building", building},
                       {"event_streams", openStreams_.load()},
                       {"durable", durable},
                       {"journal", std::move(journal)},
                       {"allocator", jemallocIsTheAllocator() ? "jemalloc" : "glibc"},
                       {"edit_threads",
                        {{"count", editWorkers_.threads()},
                         {"nice", editWorkers_.niceness()},
                         {"heavy_nice", editWorkers_.heavyNiceness()},
                         {"heavy_queued", editWorkers_.heavyQueued()}}},
                       {"costly_image_threads",
                        {{"count", costlyImages_.threads()},
                         {"nice", costlyImages_.niceness()},
                         {"queued", costlyImages_.queued()}}},
                       {"limits",
                        {{"max_body_bytes", options_.maxBodyBytes},
                         {"max_scenes", options_.maxScenes},
                         {"max_event_streams", kMaxEventStreams},
                         {"worker_threads", kWorkerThreads},
                         {"max_image_side", kMaxImageSide},
                         {"image_memory_bytes", options_.imageMemoryBytes},
                         {"scene_bytes", options_.engine.limits.bytes}}}});
           }));

  http.Get("/api/scenes", guarded([this](const httplib::Request&, httplib::Response& res) {
             std::vector<std::shared_ptr<SceneSession>> sessions;
             {
               std::lock_guard lock(scenesMutex_);
               for (const auto& [id, session] : scenes_)
                 if (session) sessions.push_back(session);
             }
             json list = json::array();
             for (const auto& session : sessions) {
               json summary = sceneSummaryJson(*session->snapshot());
               summary["state"] = "ready";
               if (const auto stall = stallOf(*session)) {  // restore stopped short (SceneStall)
                 summary["stalled_at"] = stall->version;
                 summary["problem"] = stall->problem;
               }
               list.push_back(std::move(summary));
             }
             for (json& building : buildsJson()) list.push_back(std::move(building));
             sendJson(res, 200, {{"scenes", std::move(list)}});
           }));

  http.Post("/api/scenes",
            readingBody(
                options_.maxBodyBytes,
                guarded([this](const httplib::Request& req, httplib::Response& res) {
                  // Scene JSON as the body, or a file to import (?format=obj|gltf|glb,
                  // docs/API.md).
                  const std::optional<SceneUpload> upload = sceneUploadOf(req);
                  const std::string ticket = ticketOf(req);
                  std::string name = queryText(req, "name").value_or(
                      upload ? upload->fileName : std::string("scene"));
                  std::shared_ptr<BuildJob> job;
                  Scene scene;
                  json importJson;
                  if (upload) {
                    job = reserveBuild(name, name, ticket);  // listed as building from now on
                    job->note("import");
                    const auto start = Clock::now();
                    try {
                      interchange::ImportResult imported = interchange::importSceneBytes(
                          upload->bytes, upload->fileName, upload->mtlFiles, upload->options);
                      scene = std::move(imported.scene);
                      // Names from the file become ids the API answers with: refuse bad bytes.
                      if (const auto bad = invalidUtf8Path(scene))
                        throw ApiError(400, error_code::kInvalidUtf8, *bad,
                                       "a name in the imported file is not valid UTF-8");
                      importJson = imported.report.toJson();
                    } catch (const protocol::ValidationError& error) {
                      abandonBuild(*job);
                      throw ApiError(422, error_code::kInvalidScene, error.path(), error.problem());
                    } catch (...) {
                      abandonBuild(*job);
                      throw;
                    }
                    importJson["seconds"] =
                        std::chrono::duration<double>(Clock::now() - start).count();
                  } else {
                    const json body = parseBody(req);
                    try {
                      scene = protocol::sceneFromJson(body);
                    } catch (const protocol::ValidationError& error) {
                      throw ApiError(422, error_code::kInvalidScene, error.path(), error.problem());
                    }
                    job = reserveBuild(name, name, ticket);
                  }
                  std::string id;
                  try {
                    id = buildScene(job, std::move(scene), name);
                  } catch (const std::invalid_argument& error) {  // geometry the engine refuses
                    throw ApiError(422, error_code::kInvalidScene, "", error.what());
                  } catch (const ResourceLimitError& error) {  // nothing was created
                    throw ApiError(507, error_code::kResourceLimit, "limits." + error.limit(),
                                   error.what());
                  }
                  const auto snapshot = findScene(id)->snapshot();
                  res.set_header("Location", "/api/scenes/" + id);
                  json body201 = sceneSummaryJson(*snapshot);
                  body201["build_seconds"] = snapshot->buildStats.seconds.total();
                  if (upload) body201["import"] = std::move(importJson);
                  sendJson(res, 201, body201);
                })));

  http.Get(scenePath, guarded([this](const httplib::Request& req, httplib::Response& res) {
             if (const auto job = findBuild(req.matches[1])) {  // its progress while it builds
               sendJson(res, 200, job->toJson());
               return;
             }
             const auto session = findScene(req.matches[1]);
             const auto snapshot = session->snapshot();
             json body = {{"id", snapshot->id},
                          {"name", snapshot->name},
                          {"state", "ready"},
                          {"version", snapshot->version},
                          {"scene", protocol::sceneToJson(snapshot->scene)},
                          {"volumes", volumesInfoJson(snapshot->scene)}};
             if (const auto stall = stallOf(*session)) {
               body["stalled_at"] = stall->version;
               body["problem"] = stall->problem;
             }
             sendJson(res, 200, body);
           }));

  http.Delete(scenePath,
              readingBody(options_.maxBodyBytes,
                          guarded([this](const httplib::Request& req, httplib::Response& res) {
                            if (cancelBuild(req.matches[1]) && !servesScene(req.matches[1])) {
                              res.status = 204;  // cancelled: nothing was journaled
                              return;
                            }
                            // Restoring: cancelled, and its rows removed by the restoring thread
                            // (else it was served first, and is deleted below as any scene).
                            if (const auto ended = cancelRestore(req.matches[1]); ended && !ended->served) {
                              if (!ended->deleted)
                                throw ApiError(503, error_code::kJournalFailed, "",
                                               "the journal could not record the deletion (" +
                                                   ended->problem + "); the scene was not deleted");
                              res.status = 204;
                              return;
                            }
                            const auto session = findScene(req.matches[1]);
                            journalRemove(*session);  // first: if it fails, the scene stays
                            {
                              std::lock_guard lock(scenesMutex_);
                              const auto it = scenes_.find(req.matches[1]);
                              if (it == scenes_.end() || it->second != session)
                                throw ApiError(
                                    404, error_code::kNotFound, "id",
                                    "no scene with id '" + std::string(req.matches[1]) + "'");
                              scenes_.erase(it);
                            }
                            session->close();
                            removeUploadsOf(session->id());  // the journal no longer names them
                            res.status = 204;
                          })));

  http.Post(scenePath + "/rebuild",
            readingBody(options_.maxBodyBytes,
                        guarded([this](const httplib::Request& req, httplib::Response& res) {
                          const auto session = findScene(req.matches[1]);
                          // Cancelled by the scene's DELETE (it closes the session) or a stop,
                          // at the engine's next progress report.
                          struct Cancelled : std::runtime_error {
                            Cancelled() : std::runtime_error("rebuild cancelled") {}
                          };
                          try {
                            sendJson(res, 200, rebuildJson(session->rebuild(
                                                   [&](const char*, size_t, size_t) {
                                                     if (session->closed() || stopping_)
                                                       throw Cancelled();
                                                   })));
                          } catch (const Cancelled&) {
                            throw ApiError(409, error_code::kRebuildCancelled, "",
                                           session->closed()
                                               ? "the rebuild was cancelled: the scene was deleted"
                                               : "the rebuild was cancelled: the server is stopping");
                          }
                        })));

  http.Get(
      scenePath + "/stats", guarded([this](const httplib::Request& req, httplib::Response& res) {
        const auto session = findScene(req.matches[1]);
        const auto snapshot = session->snapshot();
        const auto rebuild = session->lastRebuild();
        sendJson(res, 200,
                 {{"id", snapshot->id},
                  {"name", snapshot->name},
                  {"version", snapshot->version},
                  {"build", protocol::buildStatsToJson(snapshot->buildStats)},
                  {"mesh",
                   {{"receivers", snapshot->receiverCount()},
                    {"parts", snapshot->parts.size()},
                    {"vertices", snapshot->vertexCount()},
                    {"triangles", snapshot->triangleCount()},
                    {"tolerance", options_.engine.meshTolerance}}},
                  {"last_frame", snapshot->lastFrame ? protocol::frameResultToJson(
                                                           *snapshot->lastFrame, snapshot->scene)
                                                     : json(nullptr)},
                  {"last_rebuild", rebuild ? rebuildJson(*rebuild) : json(nullptr)}});
      }));
}

}  // namespace penumbra::server
