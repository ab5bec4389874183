// GET /api/scenes/{id}/events: server-sent events, one per new version (coalesced), and one per
// change of a render's progress or state on the scene (`event: render`, RenderJob::toJson).
// GET /api/builds/events: one per change of a scene build's progress, and its end (`event: build`).
#include <httplib.h>

#include <chrono>
#include <map>
#include <thread>

#include "server/http_server.h"
#include "server/request_io.h"
#include "server/response_json.h"

namespace penumbra::server {

using nlohmann::json;

namespace {

using Clock = std::chrono::steady_clock;

// How often an idle event stream checks for shutdown, and sends a keep-alive comment.
constexpr std::chrono::milliseconds kStreamPoll{200};
constexpr std::chrono::seconds kStreamKeepAlive{
    5};  // also how soon a closed stream frees its worker
// How often the builds' stream looks at the builds (their progress is recorded 10 times a second).
constexpr std::chrono::milliseconds kBuildPoll{100};

// What of a build's entry (BuildJob::toJson) makes a new event: all but the seconds, which count
// on by themselves.
json buildChange(json build) {
  if (build.contains("progress")) build["progress"].erase("elapsed_seconds");
  return build;
}

// The event of a build that left the list (built, failed or cancelled: its POST says which).
json buildEnded(const json& last) {
  json ended = {{"id", last["id"]}, {"name", last["name"]}, {"state", "ended"}};
  if (last.contains("ticket")) ended["ticket"] = last["ticket"];
  return ended;
}

}  // namespace

void HttpServer::registerEventRoutes() {
  httplib::Server& http = *http_;
  const std::string scenePath = std::string("/api/scenes/") + kIdPattern;

  // Counts a stream opened (closed by the provider's release), or refuses it past the bound.
  auto openStream = [this] {
    if (++openStreams_ > kMaxEventStreams) {
      --openStreams_;
      throw ApiError(429, error_code::kTooManyStreams, "",
                     "already " + std::to_string(kMaxEventStreams) +
                         " event streams open; close one first");
    }
  };

  http.Get(scenePath + "/events",
           guarded([this, openStream](const httplib::Request& req, httplib::Response& res) {
             const auto session = findScene(req.matches[1]);
             openStream();
             struct StreamState {
               std::optional<uint64_t> announced;  // last version sent
               Clock::time_point lastWrite = Clock::now();
               std::map<std::string, uint64_t> renders;  // ticket → reports and state last sent
             };
             const std::string sceneId = req.matches[1];
             auto state = std::make_shared<StreamState>();
             res.set_header("Cache-Control", "no-store");
             res.set_header("X-Accel-Buffering", "no");
             res.set_chunked_content_provider(
                 "text/event-stream",
                 guardedProvider([this, session, state, sceneId](size_t, httplib::DataSink& sink) {
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
                     return write("retry: 1000\nevent: version\ndata: " + jsonText(hello) + "\n\n");
                   }
                   const auto now = session->waitForVersionAfter(*state->announced, kStreamPoll);
                   if (stopping_ || session->closed()) {
                     sink.done();
                     return true;
                   }
                   std::map<std::string, uint64_t> renders;  // those listed now
                   for (const auto& job : renders_.ofScene(sceneId)) {
                     const uint64_t seen = job->reports() * 4 + uint64_t(job->state());
                     renders[job->ticket()] = seen;
                     const auto it = state->renders.find(job->ticket());
                     if (it != state->renders.end() && it->second == seen) continue;
                     if (!write("event: render\ndata: " + jsonText(job->toJson()) + "\n\n"))
                       return false;
                   }
                   state->renders = std::move(renders);
                   if (now->version > *state->announced) {
                     // Coalesced: one event covers every version since the last one sent.
                     const json event = changedAtJson(*now, *state->announced);
                     state->announced = now->version;
                     return write("event: version\ndata: " + jsonText(event) + "\n\n");
                   }
                   if (Clock::now() - state->lastWrite > kStreamKeepAlive)
                     return write(": keep-alive\n\n");
                   return true;
                 }),
                 [this](bool) { --openStreams_; });
           }));

  // Every scene being built: its entry (as GET /api/scenes lists it) when it appears and each time
  // its stage, counts or cancel flag change, then {"id", "name", "ticket"?, "state": "ended"}.
  http.Get("/api/builds/events",
           guarded([this, openStream](const httplib::Request&, httplib::Response& res) {
             openStream();
             struct StreamState {
               bool opened = false;
               Clock::time_point lastWrite = Clock::now();
               std::map<std::string, json> sent;  // id → the build's entry last sent
             };
             auto state = std::make_shared<StreamState>();
             res.set_header("Cache-Control", "no-store");
             res.set_header("X-Accel-Buffering", "no");
             res.set_chunked_content_provider(
                 "text/event-stream",
                 guardedProvider([this, state](size_t, httplib::DataSink& sink) {
                   auto write = [&](const std::string& text) {
                     state->lastWrite = Clock::now();
                     return sink.write(text.data(), text.size());
                   };
                   if (state->opened) std::this_thread::sleep_for(kBuildPoll);
                   if (stopping_) {
                     sink.done();
                     return true;
                   }
                   std::string out = state->opened ? "" : "retry: 1000\n\n";
                   state->opened = true;
                   std::map<std::string, json> listed;
                   for (json& build : buildsJson()) {
                     const std::string id = build["id"];
                     const auto it = state->sent.find(id);
                     if (it == state->sent.end() || buildChange(it->second) != buildChange(build))
                       out += "event: build\ndata: " + jsonText(build) + "\n\n";
                     else
                       build = it->second;  // unchanged: compared with what was sent
                     listed.emplace(id, std::move(build));
                   }
                   for (const auto& [id, last] : state->sent)
                     if (!listed.count(id))
                       out += "event: build\ndata: " + jsonText(buildEnded(last)) + "\n\n";
                   state->sent = std::move(listed);
                   if (!out.empty()) return write(out);
                   if (Clock::now() - state->lastWrite > kStreamKeepAlive)
                     return write(": keep-alive\n\n");
                   return true;
                 }),
                 [this](bool) { --openStreams_; });
           }));
}

}  // namespace penumbra::server
