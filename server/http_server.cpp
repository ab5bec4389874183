#include "server/http_server.h"

#include <httplib.h>
#include <strings.h>

#include <cctype>
#include <filesystem>

#include "protocol/scene_json.h"
#include "server/api_errors.h"
#include "server/body_reader.h"
#include "server/elastic_pool.h"
#include "server/gzip_encoding.h"
#include "server/range_limits.h"
#include "server/request_io.h"

namespace penumbra::server {

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

bool isLoopbackHost(const std::string& host) {
  return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

namespace {

// Our request bodies are JSON or files, never HTML forms, but `curl --data-binary @f` labels
// them application/x-www-form-urlencoded: httplib would then parse the body as query
// parameters and refuse one over its compiled-in form limit (8 KiB) with 413. The label is
// changed before the body is read. (httplib's routing owns the Request, which is not const.)
void bodiesAreNotForms(const httplib::Request& req) noexcept {
  auto& headers = const_cast<httplib::Request&>(req).headers;
  for (auto& [name, value] : headers)
    if (strcasecmp(name.c_str(), "Content-Type") == 0 &&
        strncasecmp(value.c_str(), "application/x-www-form-urlencoded", 33) == 0)
      value = "application/octet-stream";
}

// httplib compresses text and JSON answers per request, with brotli at its slowest quality when
// the client accepts it (3.5 s for three.js's 1.3 MB module; gzip 0.08 s): offer it gzip only.
// (Static files carry their own gzip, compressed once: StaticFiles.)
void gzipNotBrotli(const httplib::Request& req) {
  auto& headers = const_cast<httplib::Request&>(req).headers;
  const auto it = headers.find("Accept-Encoding");
  if (it == headers.end() || it->second.find("br") == std::string::npos) return;
  const bool gzip = acceptsGzip(it->second);
  headers.erase("Accept-Encoding");
  if (gzip) headers.emplace("Accept-Encoding", "gzip");
}

}  // namespace

HttpServer::HttpServer(ServerOptions options)
    : options_(std::move(options)),
      imageBudget_(options_.imageMemoryBytes),
      editWorkers_(0, options_.editNiceness, kHeavyEditNiceness),
      costlyImages_(kCostlyImageThreads, kCostlyImageNiceness, true),
      http_(std::make_unique<ConnectionServer>(options_.connections)) {
  if (!isLoopbackHost(options_.host) && options_.token.empty())
    throw std::invalid_argument("listening on " + options_.host +
                                " (not loopback) needs a token: --token T or PENUMBRA_TOKEN");
  if (!options_.dataDir.empty())
    journal_ = std::make_unique<SceneJournal>(options_.dataDir, options_.journalDatabase);
  // Every open connection (an event stream, a slow client) holds a worker for its lifetime
  // (DEPENDENCIES.md): the pool grows with them.
  http_->new_task_queue = [] {
    return new ElasticPool(kMinWorkerThreads, kWorkerThreads, kWorkerIdleSeconds);
  };
  http_->set_payload_max_length(options_.maxBodyBytes);
  http_->set_keep_alive_max_count(1000);
  http_->set_keep_alive_timeout(2);  // idle keep-alive connections hold a worker too
  http_->set_tcp_nodelay(true);
  // cpp-httplib's default sets SO_REUSEPORT, which lets a second server bind the same port and
  // take half the connections (issue 36): SO_REUSEADDR only (a restart may rebind at once).
  http_->set_socket_options([this](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, reinterpret_cast<void*>(&yes), sizeof(yes));
    listenSocket_ = sock;  // for its backlog (bind)
  });
  http_->set_logger(
      [this](const httplib::Request&, const httplib::Response&) { trimmer_.noteActivity(); });
  const size_t maxBody = options_.maxBodyBytes;
  http_->set_error_handler(httplib::Server::HandlerWithResponse(
      [maxBody](const httplib::Request& req, httplib::Response& res) noexcept {
        // Statuses httplib set itself (no route, body too large, unreadable request)
        // still answer with the JSON error shape; handler-written bodies are kept. The
        // path may hold any bytes (`GET /%ff`): sendJson replaces invalid UTF-8.
        if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
        try {
          // A head the connection refused (too slow, too large) reaches here as httplib's 400.
          if (const auto problem = ConnectionServer::headProblem(); problem.status) {
            res.status = problem.status;
            res.set_header("Connection", "close");
            res.set_content(problem.body, "application/json");
            return httplib::Server::HandlerResponse::Handled;
          }
          sendJson(res, res.status, errorJsonForStatus(res.status, req.method, req.path, maxBody));
        } catch (...) {
          res.set_content(kInternalErrorBody, "application/json");
        }
        return httplib::Server::HandlerResponse::Handled;
      }));
  http_->set_exception_handler(
      [](const httplib::Request& req, httplib::Response& res, std::exception_ptr error) noexcept {
        try {
          if (error) std::rethrow_exception(error);
          sendInternalError(req, res, "unknown exception");
        } catch (const std::bad_alloc&) {
          sendInternalError(req, res, "out of memory", true);
        } catch (const JournalUnavailable& e) {  // any route that needed the journal: 503
          try {
            sendError(res, journalUnavailableError(e));
          } catch (...) {
            sendInternalError(req, res, e.what());
          }
        } catch (const std::exception& e) {
          sendInternalError(req, res, e.what());
        } catch (...) {
          sendInternalError(req, res, "unknown exception");
        }
      });
  http_->set_pre_routing_handler(httplib::Server::HandlerWithResponse(
      [this](const httplib::Request& req, httplib::Response& res) noexcept {
        bodiesAreNotForms(req);
        gzipNotBrotli(req);
        try {
          if (refuseForeignOrigin(req, res) || refuseAccess(req, res) ||
              refuseHostileRanges(req, res))
            return httplib::Server::HandlerResponse::Handled;
        } catch (...) {
          res.status = 500;
          res.set_content(kInternalErrorBody, "application/json");
          return httplib::Server::HandlerResponse::Handled;
        }
        return httplib::Server::HandlerResponse::Unhandled;
      }));
  registerRoutes();
  registerStaticFiles();
  if (journal_ && !options_.journalDatabase.empty()) startLeases();
}

HttpServer::~HttpServer() {
  stop();
  {
    std::lock_guard lock(scenesMutex_);
    for (auto& [id, session] : scenes_)
      if (session) session->close();
  }
  // An ephemeral server's uploaded volumes die with it (a journal's stay for its restart).
  if (options_.dataDir.empty() && !uploadDir_.empty()) {
    std::error_code ignored;
    std::filesystem::remove_all(uploadDir_, ignored);
  }
}

std::shared_ptr<SceneSession> HttpServer::findScene(const std::string& id) {
  {
    std::lock_guard lock(scenesMutex_);
    const auto it = scenes_.find(id);
    if (it != scenes_.end() && !it->second && restoring_.count(id))
      throw ApiError(503, error_code::kRestoring, "id",
                     "scene '" + id + "' is being restored from the journal; retry in a moment");
    if (it != scenes_.end() && !it->second && builds_.count(id))
      throw ApiError(503, error_code::kBuilding, "id",
                     "scene '" + id + "' is being built; retry in a moment (GET /api/scenes/" +
                         id + " says how far it is)");
    if (it != scenes_.end() && it->second) {
      if (leases_) lastUse_[id] = std::chrono::steady_clock::now();
      return it->second;
    }
    if (it != scenes_.end() || !leases_ || stopping_)
      throw ApiError(404, error_code::kNotFound, "id", "no scene with id '" + id + "'");
    scenes_.emplace(id, nullptr);  // another node's, or nobody's: restoring while taken over
    restoring_.emplace(id, std::make_shared<RestoreJob>(id));
  }
  return takeOver(id);
}

std::string HttpServer::freshId(const std::string& preferred) {
  const std::string base = sceneIdFromName(preferred);
  if (!base.empty() && !scenes_.count(base)) return base;
  for (;;) {
    std::string id = (base.empty() ? "s" : base + "-") + std::to_string(nextId_++);
    if (!scenes_.count(id)) return id;
  }
}

bool HttpServer::hasScene(const std::string& id) const {
  std::lock_guard lock(scenesMutex_);
  return scenes_.count(id) > 0;
}

int HttpServer::bind() {
  port_ = options_.port == 0
              ? http_->bind_to_any_port(options_.host)
              : (http_->bind_to_port(options_.host, options_.port) ? options_.port : -1);
  if (port_ <= 0)
    throw std::runtime_error("cannot listen on " + options_.host + ":" +
                             std::to_string(options_.port) + " (address in use or not available)");
  // cpp-httplib 0.11 listens with a backlog of 5: a burst of connections overflowed it and each
  // connection past it waited a second for its SYN to be sent again (500 clients took 45 s to
  // connect). Listening again on the bound socket only changes the backlog.
  if (listenSocket_ >= 0) ::listen(listenSocket_, kListenBacklog);
  return port_;
}

void HttpServer::listen() { http_->listen_after_bind(); }

void HttpServer::stop() {
  stopping_ = true;
  {
    std::lock_guard lock(scenesMutex_);
    for (auto& [id, job] : builds_) job->cancel();  // their requests end at the next report
    for (auto& [id, job] : restoring_) job->cancel();  // the journal as it was: back next start
  }
  renders_.cancelAll("the server is stopping");
  http_->stop();
  stopLeases();
}

bool HttpServer::isRunning() const { return http_->is_running(); }

size_t HttpServer::connectionsFrom(const std::string& address) const {
  return static_cast<const ConnectionServer&>(*http_).connectionsFrom(address);
}

void HttpServer::registerStaticFiles() {
  namespace fs = std::filesystem;
  if (options_.staticDir.empty()) return;
  const fs::path dir(options_.staticDir);
  if (!fs::is_directory(dir))
    throw std::runtime_error("--static: no directory '" + options_.staticDir + "'");
  // three.js from npm, for the page's import map: node_modules inside the page's
  // folder or beside it (a package.json at the repository root). Its files change only with
  // npm ci, so browsers may keep them an hour; the page's own files are revalidated (ETag) on
  // every load, so an edited file shows at once.
  for (const fs::path& modules : {dir / "node_modules", dir.parent_path() / "node_modules"})
    if (fs::is_directory(modules)) {
      staticRoots_.emplace_back("/node_modules/", fs::canonical(modules).string());
      staticFiles_.mount("/node_modules/", fs::canonical(modules), "public, max-age=3600");
      break;
    }
  staticRoots_.emplace_back("/", fs::canonical(dir).string());
  staticFiles_.mount("/", fs::canonical(dir), "no-cache");
  // After every API route (httplib tries GET routes in registration order).
  http_->Get(R"(/.*)", [this](const httplib::Request& req, httplib::Response& res) {
    if (req.path.rfind("/api/", 0) == 0 || !staticFiles_.serve(req, res)) res.status = 404;
  });
}

void HttpServer::registerRoutes() {
  registerSceneRoutes();
  registerEditRoutes();
  registerMeshRoutes();
  registerImageRoutes();
  registerEventRoutes();
  registerVolumeRoutes();
  registerRenameRoutes();
  registerBodyFallbacks();  // last: httplib tries content-reader routes in order
}

// A request with a body to any other path or method is read within the limit too, then
// answered 404 (or 413): httplib would read it whole first, without bound when chunked.
void HttpServer::registerBodyFallbacks() {
  const size_t maxBody = options_.maxBodyBytes;
  const auto notFound = [maxBody](const httplib::Request& req, httplib::Response& res) {
    sendJson(res, 404, errorJsonForStatus(404, req.method, req.path, maxBody));
  };
  http_->Post(".*", readingBody(maxBody, notFound));
  http_->Put(".*", readingBody(maxBody, notFound));
  http_->Patch(".*", readingBody(maxBody, notFound));
  http_->Delete(".*", readingBody(maxBody, notFound));
}

}  // namespace penumbra::server
