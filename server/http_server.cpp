#include "server/http_server.h"

#include <httplib.h>

#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <thread>

#include "core/render/renderer.h"
#include "interchange/glb_export.h"
#include "interchange/scene_import.h"
#include "protocol/edits_json.h"
#include "protocol/frame_result_json.h"
#include "protocol/json_reader.h"
#include "protocol/json_text.h"
#include "protocol/scene_json.h"
#include "server/api_errors.h"
#include "server/gzip_encoding.h"
#include "server/image_encoding.h"
#include "server/mesh_binary.h"
#include "server/scene_upload.h"

namespace penumbra::server {

namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

// Scene ids in URLs: letters, digits, '_', '-', '.' (so file stems work).
const char* const kIdPattern = "([A-Za-z0-9_.-]+)";
constexpr size_t kMaxIdLength = 64;
// How often an idle event stream checks for shutdown, and sends a keep-alive comment.
constexpr std::chrono::milliseconds kStreamPoll{200};
constexpr std::chrono::seconds kStreamKeepAlive{
    5};  // also how soon a closed stream frees its worker

void sendJson(httplib::Response& res, int status, const json& body) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(body.dump(), "application/json");
}

void sendError(httplib::Response& res, const ApiError& error, const json& extra = json::object()) {
  sendJson(res, error.status(), errorJson(error.code(), error.what(), error.path(), extra));
}

// Request bodies: size was checked by httplib (413); here syntax and depth.
json parseBody(const httplib::Request& req) {
  if (req.body.empty())
    throw ApiError(400, error_code::kMalformedJson, "(json)",
                   "the request body is empty; send a JSON document");
  try {
    return protocol::parseJsonText(req.body, kMaxBodyBytes, protocol::kMaxJsonDepth);
  } catch (const protocol::ValidationError& error) {
    throw ApiError(400, error_code::kMalformedJson, error.path(), error.problem());
  }
}

// Query parameters: absent → nullopt; present but not what we need → 400 naming `query.<name>`.
std::optional<std::string> queryText(const httplib::Request& req, const char* name) {
  if (!req.has_param(name)) return std::nullopt;
  return req.get_param_value(name);
}

std::optional<uint64_t> queryUnsigned(const httplib::Request& req, const char* name, uint64_t min,
                                      uint64_t max) {
  const auto text = queryText(req, name);
  if (!text) return std::nullopt;
  uint64_t value = 0;
  const auto [end, ec] = std::from_chars(text->data(), text->data() + text->size(), value);
  if (ec != std::errc() || end != text->data() + text->size() || text->empty() || value < min ||
      value > max)
    throw ApiError(400, error_code::kBadParameter, std::string("query.") + name,
                   std::string(name) + " must be an integer in [" + std::to_string(min) + ", " +
                       std::to_string(max) + "], got '" + *text + "'");
  return value;
}

std::optional<double> queryNumber(const httplib::Request& req, const char* name) {
  const auto text = queryText(req, name);
  if (!text) return std::nullopt;
  try {
    size_t used = 0;
    const double value = std::stod(*text, &used);
    if (used == text->size() && std::isfinite(value)) return value;
  } catch (const std::exception&) {
  }
  throw ApiError(400, error_code::kBadParameter, std::string("query.") + name,
                 std::string(name) + " must be a finite number, got '" + *text + "'");
}

std::optional<Vec3> queryVec3(const httplib::Request& req, const char* name) {
  const auto text = queryText(req, name);
  if (!text) return std::nullopt;
  Vec3 v{0.0};
  size_t start = 0;
  for (int c = 0; c < 3; ++c) {
    const size_t comma = text->find(',', start);
    if ((c < 2) != (comma != std::string::npos)) break;
    const std::string part = text->substr(start, c < 2 ? comma - start : std::string::npos);
    try {
      size_t used = 0;
      v[c] = std::stod(part, &used);
      if (used != part.size() || !std::isfinite(v[c])) break;
    } catch (const std::exception&) {
      break;
    }
    if (c == 2) return v;
    start = comma + 1;
  }
  throw ApiError(400, error_code::kBadParameter, std::string("query.") + name,
                 std::string(name) + " must be three finite numbers 'x,y,z', got '" + *text + "'");
}

// The camera of an image request: the scene's camera (or the default one) with
// any of the query's camera parameters replacing its fields.
Camera cameraFromQuery(const httplib::Request& req, const Scene& scene) {
  Camera camera = scene.camera().value_or(Camera{});
  if (auto v = queryVec3(req, "position")) camera.position = *v;
  if (auto v = queryVec3(req, "target")) camera.target = *v;
  if (auto v = queryVec3(req, "up")) camera.up = *v;
  if (auto p = queryText(req, "projection")) {
    if (*p == "perspective")
      camera.projection = Camera::Projection::Perspective;
    else if (*p == "orthographic")
      camera.projection = Camera::Projection::Orthographic;
    else
      throw ApiError(400, error_code::kBadParameter, "query.projection",
                     "projection must be 'perspective' or 'orthographic', got '" + *p + "'");
  }
  if (auto v = queryNumber(req, "fov_y_deg")) {
    if (!(*v > 0 && *v < 180))
      throw ApiError(400, error_code::kBadParameter, "query.fov_y_deg",
                     "fov_y_deg must be in (0, 180)");
    camera.fovYDeg = *v;
  }
  // (`height` is the image's; the orthographic view's height is `ortho_height`.)
  if (auto v = queryNumber(req, "ortho_height")) {
    if (!(*v > 0))
      throw ApiError(400, error_code::kBadParameter, "query.ortho_height",
                     "ortho_height must be positive");
    camera.height = *v;
  }
  if (auto v = queryNumber(req, "near")) camera.near = *v;
  if (auto v = queryNumber(req, "far")) camera.far = *v;
  if (!(camera.near > 0 && camera.far > camera.near))
    throw ApiError(400, error_code::kBadParameter, "query.near", "need 0 < near < far");
  if (glm::length(camera.target - camera.position) == 0)
    throw ApiError(400, error_code::kBadParameter, "query.target",
                   "target must differ from position");
  return camera;
}

json buildStatsJson(const BuildStats& s) {
  const BuildTimings& t = s.seconds;
  return {{"faces", s.faces},
          {"receivers", s.receivers},
          {"lights", s.lights},
          {"candidate_pairs", s.candidatePairs},
          {"pairs_with_shadow", s.pairsWithShadow},
          {"tree_nodes", s.treeNodes},
          {"cells", s.cells},
          {"vertices",
           {{"total", s.vertices},
            {"lit", s.litVertices},
            {"penumbra", s.penumbraVertices},
            {"umbra", s.umbraVertices}}},
          {"seconds",
           {{"ordering", t.ordering},
            {"cube", t.cube},
            {"casting_and_merging", t.castingAndMerging},
            {"illumination", t.illumination},
            {"triangulation", t.triangulation},
            {"total", t.total()}}}};
}

json rebuildJson(const RebuildReport& r) {
  return {{"version", r.version},
          {"seconds",
           {{"build", r.buildSeconds},
            {"mesh", r.meshSeconds},
            {"total", r.buildSeconds + r.meshSeconds}}},
          {"mesh", {{"vertices", r.meshVertices}, {"triangles", r.meshTriangles}}},
          {"served_mesh", {{"vertices", r.servedVertices}, {"triangles", r.servedTriangles}}},
          {"stats", buildStatsJson(r.stats)}};
}

json sceneSummaryJson(const SceneSnapshot& s) {
  return {{"id", s.id},
          {"name", s.name},
          {"version", s.version},
          {"objects", s.scene.objects().size()},
          {"faces", s.scene.faces().size()},
          {"receivers", s.receiverCount()},
          {"url", "/api/scenes/" + s.id}};
}

// Receivers whose mesh changed in this version, and those that left the scene in it.
json changedAtJson(const SceneSnapshot& s, uint64_t after) {
  const MeshSelection selection = s.select(after);
  json changed = json::array(), removed = json::array();
  for (const ReceiverKey& key : selection.receivers) changed.push_back(toJson(key));
  for (const ReceiverKey& key : selection.removed) removed.push_back(toJson(key));
  return {{"version", s.version}, {"changed", std::move(changed)}, {"removed", std::move(removed)}};
}

// "edits[3].transform" → 3 (the edit a frame error is in), or -1.
long editIndexOf(const std::string& path) {
  static const std::regex pattern(R"(^edits\[(\d+)\].*)");
  std::smatch match;
  if (std::regex_match(path, match, pattern)) return std::stol(match[1]);
  return -1;
}

std::string sceneIdFromName(const std::string& name) {
  std::string id;
  for (char c : name) {
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')
      id += c;
    else if (c == '.')
      break;  // "cubes15.scene.json" → "cubes15"
  }
  return id.substr(0, kMaxIdLength);
}

}  // namespace

HttpServer::HttpServer(ServerOptions options)
    : options_(std::move(options)), http_(std::make_unique<httplib::Server>()) {
  // Every open event stream holds a worker for its lifetime (DEPENDENCIES.md): the
  // pool has one per allowed stream plus kRequestWorkers for everything else.
  http_->new_task_queue = [] { return new httplib::ThreadPool(kWorkerThreads); };
  http_->set_payload_max_length(kMaxBodyBytes);
  http_->set_keep_alive_max_count(1000);
  http_->set_keep_alive_timeout(2);  // idle keep-alive connections hold a worker too
  http_->set_tcp_nodelay(true);
  http_->set_file_extension_and_mimetype_mapping("js", "text/javascript");
  http_->set_file_extension_and_mimetype_mapping("mjs", "text/javascript");
  http_->set_file_extension_and_mimetype_mapping("glb", "model/gltf-binary");
  http_->set_file_extension_and_mimetype_mapping("wasm", "application/wasm");
  const size_t maxBody = kMaxBodyBytes;
  http_->set_error_handler(httplib::Server::HandlerWithResponse(
      [maxBody](const httplib::Request& req, httplib::Response& res) {
        // Statuses httplib set itself (no route, body too large, unreadable request)
        // still answer with the JSON error shape; handler-written bodies are kept.
        if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
        res.set_content(errorJsonForStatus(res.status, req.method, req.path, maxBody).dump(),
                        "application/json");
        return httplib::Server::HandlerResponse::Handled;
      }));
  http_->set_exception_handler(
      [](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
        sendJson(res, 500, errorJson(error_code::kInternal, "internal error", ""));
      });
  registerRoutes();
  registerStaticFiles();
}

HttpServer::~HttpServer() {
  stop();
  std::lock_guard lock(scenesMutex_);
  for (auto& [id, session] : scenes_)
    if (session) session->close();
}

std::shared_ptr<SceneSession> HttpServer::findScene(const std::string& id) const {
  std::lock_guard lock(scenesMutex_);
  const auto it = scenes_.find(id);
  if (it == scenes_.end() || !it->second)
    throw ApiError(404, error_code::kNotFound, "id", "no scene with id '" + id + "'");
  return it->second;
}

std::string HttpServer::freshId(const std::string& preferred) {
  const std::string base = sceneIdFromName(preferred);
  if (!base.empty() && !scenes_.count(base)) return base;
  for (;;) {
    std::string id = (base.empty() ? "s" : base + "-") + std::to_string(nextId_++);
    if (!scenes_.count(id)) return id;
  }
}

std::string HttpServer::addScene(Scene scene, const std::string& name,
                                 const std::string& preferredId) {
  std::string id;
  {
    std::lock_guard lock(scenesMutex_);
    if (scenes_.size() >= kMaxScenes)
      throw ApiError(
          429, error_code::kTooManyScenes, "",
          "the server already holds " + std::to_string(kMaxScenes) + " scenes; DELETE one first");
    id = freshId(preferredId.empty() ? name : preferredId);
    scenes_.emplace(id, nullptr);  // reserved while it builds
  }
  // Build outside the lock: a large scene takes seconds and other scenes keep serving.
  std::shared_ptr<SceneSession> session;
  try {
    session = std::make_shared<SceneSession>(id, name, std::move(scene), options_.engine);
  } catch (...) {
    std::lock_guard lock(scenesMutex_);
    scenes_.erase(id);
    throw;
  }
  std::lock_guard lock(scenesMutex_);
  scenes_[id] = std::move(session);
  return id;
}

int HttpServer::bind() {
  port_ = options_.port == 0
              ? http_->bind_to_any_port(options_.host)
              : (http_->bind_to_port(options_.host, options_.port) ? options_.port : -1);
  if (port_ <= 0)
    throw std::runtime_error("cannot listen on " + options_.host + ":" +
                             std::to_string(options_.port) + " (address in use or not available)");
  return port_;
}

void HttpServer::listen() { http_->listen_after_bind(); }

void HttpServer::stop() {
  stopping_ = true;
  http_->stop();
}

bool HttpServer::isRunning() const { return http_->is_running(); }

void HttpServer::registerStaticFiles() {
  namespace fs = std::filesystem;
  if (options_.staticDir.empty()) return;
  const fs::path dir(options_.staticDir);
  if (!fs::is_directory(dir))
    throw std::runtime_error("--static: no directory '" + options_.staticDir + "'");
  // three.js from npm, for the page's import map: node_modules inside the page's
  // folder or beside it (a package.json at the repository root).
  for (const fs::path& modules : {dir / "node_modules", dir.parent_path() / "node_modules"})
    if (fs::is_directory(modules)) {
      http_->set_mount_point("/node_modules", modules.string());
      break;
    }
  http_->set_mount_point("/", dir.string());
}

void HttpServer::registerRoutes() {
  httplib::Server& http = *http_;
  const std::string scenePath = std::string("/api/scenes/") + kIdPattern;

  // Every handler: ApiError → its status; anything else → 500, never a crash.
  auto guarded = [](auto handler) {
    return [handler](const httplib::Request& req, httplib::Response& res) {
      try {
        handler(req, res);
      } catch (const ApiError& error) {
        sendError(res, error);
      } catch (const std::exception& error) {
        std::fprintf(stderr, "penumbra serve: internal error on %s %s: %s\n", req.method.c_str(),
                     req.path.c_str(), error.what());
        sendJson(
            res, 500,
            errorJson(error_code::kInternal, std::string("internal error: ") + error.what(), ""));
      }
    };
  };

  http.Get("/api/health", guarded([this](const httplib::Request&, httplib::Response& res) {
             size_t scenes = 0;
             {
               std::lock_guard lock(scenesMutex_);
               scenes = scenes_.size();
             }
             sendJson(res, 200,
                      {{"status", "ok"},
                       {"scenes", scenes},
                       {"event_streams", openStreams_.load()},
                       {"limits",
                        {{"max_body_bytes", kMaxBodyBytes},
                         {"max_scenes", kMaxScenes},
                         {"max_event_streams", kMaxEventStreams},
                         {"worker_threads", kWorkerThreads},
                         {"max_image_side", kMaxImageSide}}}});
           }));

  http.Get("/api/scenes", guarded([this](const httplib::Request&, httplib::Response& res) {
             std::vector<std::shared_ptr<SceneSession>> sessions;
             {
               std::lock_guard lock(scenesMutex_);
               for (const auto& [id, session] : scenes_)
                 if (session) sessions.push_back(session);
             }
             json list = json::array();
             for (const auto& session : sessions)
               list.push_back(sceneSummaryJson(*session->snapshot()));
             sendJson(res, 200, {{"scenes", std::move(list)}});
           }));

  http.Post("/api/scenes", guarded([this](const httplib::Request& req, httplib::Response& res) {
              // Scene JSON as the body, or a file to import (?format=obj|gltf|glb, docs/API.md).
              const std::optional<SceneUpload> upload = sceneUploadOf(req);
              Scene scene;
              std::string name = queryText(req, "name").value_or("scene");
              json importJson;
              if (upload) {
                const auto start = Clock::now();
                try {
                  interchange::ImportResult imported = interchange::importSceneBytes(
                      upload->bytes, upload->fileName, upload->mtlFiles, upload->options);
                  scene = std::move(imported.scene);
                  importJson = imported.report.toJson();
                } catch (const protocol::ValidationError& error) {
                  throw ApiError(422, error_code::kInvalidScene, error.path(), error.problem());
                }
                importJson["seconds"] = std::chrono::duration<double>(Clock::now() - start).count();
                if (!req.has_param("name")) name = upload->fileName;
              } else {
                const json body = parseBody(req);
                try {
                  scene = protocol::sceneFromJson(body);
                } catch (const protocol::ValidationError& error) {
                  throw ApiError(422, error_code::kInvalidScene, error.path(), error.problem());
                }
              }
              std::string id;
              try {
                id = addScene(std::move(scene), name, name);
              } catch (const std::invalid_argument& error) {  // geometry the engine refuses
                throw ApiError(422, error_code::kInvalidScene, "", error.what());
              }
              const auto snapshot = findScene(id)->snapshot();
              res.set_header("Location", "/api/scenes/" + id);
              json body201 = sceneSummaryJson(*snapshot);
              body201["build_seconds"] = snapshot->buildStats.seconds.total();
              if (upload) body201["import"] = std::move(importJson);
              sendJson(res, 201, body201);
            }));

  http.Get(scenePath, guarded([this](const httplib::Request& req, httplib::Response& res) {
             const auto snapshot = findScene(req.matches[1])->snapshot();
             sendJson(res, 200,
                      {{"id", snapshot->id},
                       {"name", snapshot->name},
                       {"version", snapshot->version},
                       {"scene", protocol::sceneToJson(snapshot->scene)}});
           }));

  http.Delete(scenePath, guarded([this](const httplib::Request& req, httplib::Response& res) {
                std::shared_ptr<SceneSession> session;
                {
                  std::lock_guard lock(scenesMutex_);
                  const auto it = scenes_.find(req.matches[1]);
                  if (it == scenes_.end() || !it->second)
                    throw ApiError(404, error_code::kNotFound, "id",
                                   "no scene with id '" + std::string(req.matches[1]) + "'");
                  session = it->second;
                  scenes_.erase(it);
                }
                session->close();
                res.status = 204;
              }));

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
        SceneSession::Applied applied;
        try {
          applied = session->apply(frame);
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

  http.Get(
      scenePath + "/mesh", guarded([this](const httplib::Request& req, httplib::Response& res) {
        const auto snapshot = findScene(req.matches[1])->snapshot();
        const auto since = queryUnsigned(req, "since", 0, snapshot->version);
        const std::string format = queryText(req, "format").value_or("json");
        const MeshSelection selection = snapshot->select(since);
        res.set_header("X-Penumbra-Version", std::to_string(snapshot->version));
        if (format == "json") {
          sendJson(res, 200, snapshot->meshJson(selection));
        } else if (format == "bin") {
          res.status = 200;
          res.set_header("Cache-Control", "no-store");
          std::string bytes = mesh_binary::encode(*snapshot, selection);
          // Typed arrays are not a type httplib compresses itself; gzip them when the
          // client takes it (browsers' fetch decodes it transparently).
          res.set_header("Vary", "Accept-Encoding");
          res.set_header("X-Penumbra-Uncompressed-Bytes", std::to_string(bytes.size()));
          const auto policy = options_.meshCompression;
          const bool loopback = req.remote_addr == "127.0.0.1" || req.remote_addr == "::1" ||
                                req.remote_addr.rfind("::ffff:127.", 0) == 0;
          if (policy != ServerOptions::MeshCompression::Never &&
              (policy == ServerOptions::MeshCompression::Always || !loopback) &&
              acceptsGzip(req.get_header_value("Accept-Encoding"))) {
            bytes = gzipCompress(bytes);
            res.set_header("Content-Encoding", "gzip");
          }
          res.set_content(bytes, "application/octet-stream");
        } else if (format == "glb") {
          // The whole scene's lit mesh (a viewer's file, not a delta): `since` is refused.
          if (since)
            throw ApiError(400, error_code::kBadParameter, "query.since",
                           "format=glb is always the whole mesh; drop since");
          // A fixed color_scale keeps colours comparable across versions (the default, 1 /
          // the brightest radiance channel, follows the scene).
          interchange::GlbOptions glbOptions;
          if (const auto scale = queryNumber(req, "color_scale")) {
            if (!(*scale > 0))
              throw ApiError(400, error_code::kBadParameter, "query.color_scale",
                             "color_scale must be positive");
            glbOptions.colorScale = *scale;
          }
          const interchange::GlbFile glb =
              interchange::meshToGlb(snapshot->scene, snapshot->mesh(), glbOptions);
          res.status = 200;
          res.set_header("Cache-Control", "no-store");
          res.set_header("X-Penumbra-Color-Scale", json(glb.colorScale).dump());
          res.set_header("Content-Disposition", "inline; filename=\"" + snapshot->id + ".glb\"");
          res.set_content(std::string(glb.bytes.begin(), glb.bytes.end()), "model/gltf-binary");
        } else {
          throw ApiError(400, error_code::kBadParameter, "query.format",
                         "format must be 'json', 'bin' or 'glb', got '" + format + "'");
        }
      }));

  http.Get(
      scenePath + "/image", guarded([this](const httplib::Request& req, httplib::Response& res) {
        const auto snapshot = findScene(req.matches[1])->snapshot();
        const auto width = queryUnsigned(req, "width", 1, kMaxImageSide);
        const auto height = queryUnsigned(req, "height", 1, kMaxImageSide);
        if (!width)
          throw ApiError(400, error_code::kBadParameter, "query.width",
                         "width is required (1 to " + std::to_string(kMaxImageSide) + ")");
        if (!height)
          throw ApiError(400, error_code::kBadParameter, "query.height",
                         "height is required (1 to " + std::to_string(kMaxImageSide) + ")");
        const std::string format = queryText(req, "format").value_or("png");
        if (format != "png" && format != "exr")
          throw ApiError(400, error_code::kBadParameter, "query.format",
                         "format must be 'png' or 'exr', got '" + format + "'");
        RenderSettings settings;
        settings.width = int(*width);
        settings.height = int(*height);
        settings.camera = cameraFromQuery(req, snapshot->scene);
        RenderedImage image;
        try {
          image = render(snapshot->scene, snapshot->mesh(), settings);
        } catch (const std::invalid_argument& error) {  // e.g. a degenerate camera
          throw ApiError(400, error_code::kBadParameter, "query", error.what());
        }
        const std::vector<uint8_t> bytes = format == "png" ? encodePng(image) : encodeExr(image);
        res.status = 200;
        res.set_header("Cache-Control", "no-store");
        res.set_header("X-Penumbra-Version", std::to_string(snapshot->version));
        res.set_header("X-Penumbra-Render-Seconds", std::to_string(image.seconds));
        res.set_content(std::string(bytes.begin(), bytes.end()),
                        format == "png" ? "image/png" : "image/x-exr");
      }));

  http.Post(scenePath + "/rebuild",
            guarded([this](const httplib::Request& req, httplib::Response& res) {
              const auto session = findScene(req.matches[1]);
              sendJson(res, 200, rebuildJson(session->rebuild()));
            }));

  http.Get(
      scenePath + "/stats", guarded([this](const httplib::Request& req, httplib::Response& res) {
        const auto session = findScene(req.matches[1]);
        const auto snapshot = session->snapshot();
        const auto rebuild = session->lastRebuild();
        sendJson(res, 200,
                 {{"id", snapshot->id},
                  {"name", snapshot->name},
                  {"version", snapshot->version},
                  {"build", buildStatsJson(snapshot->buildStats)},
                  {"mesh",
                   {{"receivers", snapshot->receiverCount()},
                    {"parts", snapshot->parts.size()},
                    {"vertices", snapshot->vertexCount()},
                    {"triangles", snapshot->triangleCount()}}},
                  {"last_frame", snapshot->lastFrame ? protocol::frameResultToJson(
                                                           *snapshot->lastFrame, snapshot->scene)
                                                     : json(nullptr)},
                  {"last_rebuild", rebuild ? rebuildJson(*rebuild) : json(nullptr)}});
      }));

  http.Get(scenePath + "/events",
           guarded([this](const httplib::Request& req, httplib::Response& res) {
             const auto session = findScene(req.matches[1]);
             if (++openStreams_ > kMaxEventStreams) {
               --openStreams_;
               throw ApiError(429, error_code::kTooManyStreams, "",
                              "already " + std::to_string(kMaxEventStreams) +
                                  " event streams open; close one first");
             }
             struct StreamState {
               std::optional<uint64_t> announced;  // last version sent
               Clock::time_point lastWrite = Clock::now();
             };
             auto state = std::make_shared<StreamState>();
             res.set_header("Cache-Control", "no-store");
             res.set_header("X-Accel-Buffering", "no");
             res.set_chunked_content_provider(
                 "text/event-stream",
                 [this, session, state](size_t, httplib::DataSink& sink) {
                   auto write = [&](const std::string& text) {
                     state->lastWrite = Clock::now();
                     return sink.write(text.data(), text.size());
                   };
                   if (!state->announced) {  // on connect: the current version, nothing changed
                     const auto now = session->snapshot();
                     state->announced = now->version;
                     json hello = {{"version", now->version},
                                   {"changed", json::array()},
                                   {"removed", json::array()}};
                     return write("retry: 1000\nevent: version\ndata: " + hello.dump() + "\n\n");
                   }
                   const auto now = session->waitForVersionAfter(*state->announced, kStreamPoll);
                   if (stopping_ || session->closed()) {
                     sink.done();
                     return true;
                   }
                   if (now->version > *state->announced) {
                     // Coalesced: one event covers every version since the last one sent.
                     const json event = changedAtJson(*now, *state->announced);
                     state->announced = now->version;
                     return write("event: version\ndata: " + event.dump() + "\n\n");
                   }
                   if (Clock::now() - state->lastWrite > kStreamKeepAlive)
                     return write(": keep-alive\n\n");
                   return true;
                 },
                 [this](bool) { --openStreams_; });
           }));
}

}  // namespace penumbra::server
