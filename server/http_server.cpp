#include "server/http_server.h"

#include <httplib.h>

#include <cctype>
#include <filesystem>

#include "server/api_errors.h"
#include "server/request_io.h"

namespace penumbra::server {

namespace {

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
        // The path is the client's bytes (decoded): dumpJson, never a throwing dump().
        sendJson(res, res.status, errorJsonForStatus(res.status, req.method, req.path, maxBody));
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
  registerSceneRoutes();
  registerEditRoutes();
  registerMeshRoutes();
  registerImageRoutes();
  registerEventRoutes();
}

}  // namespace penumbra::server
