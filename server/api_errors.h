// API errors: ApiError (status, stable code, key path, message) thrown by handlers,
// and errorJson, the body {"error": {...}}. Immutable values; thread-safe.
#pragma once

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace penumbra::server {

// Stable error codes (docs/API.md "Errors"); clients switch on these, not on messages.
namespace error_code {
inline constexpr const char* kMalformedJson = "malformed_json";       // 400
inline constexpr const char* kBadParameter = "bad_parameter";         // 400
inline constexpr const char* kBadRequest = "bad_request";             // 400
inline constexpr const char* kInvalidUtf8 = "invalid_utf8";           // 400
inline constexpr const char* kNotFound = "not_found";                 // 404
inline constexpr const char* kPayloadTooLarge = "payload_too_large";  // 413
inline constexpr const char* kInvalidScene = "invalid_scene";         // 422
inline constexpr const char* kInvalidFrame = "invalid_frame";         // 422
inline constexpr const char* kInvalidName = "invalid_name";           // 422
inline constexpr const char* kTooManyScenes = "too_many_scenes";      // 429
inline constexpr const char* kTooManyStreams = "too_many_streams";    // 429
inline constexpr const char* kInternal = "internal_error";            // 500
inline constexpr const char* kFrameNotApplied = "frame_not_applied";  // 500
inline constexpr const char* kOutOfMemory = "out_of_memory";          // 507
inline constexpr const char* kResourceLimit = "resource_limit";       // 507, names the limit
inline constexpr const char* kBusy = "busy";                          // 503, with Retry-After
inline constexpr const char* kNotImplemented = "not_implemented";     // 501
inline constexpr const char* kUnauthorized = "unauthorized";          // 401
inline constexpr const char* kForbiddenOrigin = "forbidden_origin";   // 403: Origin or Host
inline constexpr const char* kJournalFailed = "journal_failed";       // 503
inline constexpr const char* kRestoring =
    "restoring";  // 503 + Retry-After: back from the journal soon
inline constexpr const char* kSceneStalled = "scene_stalled";  // 409
// 503 + Retry-After: another node holds the scene's lease (docs/SERVER.md "Many nodes")
inline constexpr const char* kOwnedElsewhere = "owned_elsewhere";
inline constexpr const char* kBuilding = "building";  // 503 + Retry-After: the scene is being built
inline constexpr const char* kBuildCancelled = "build_cancelled";  // 409: DELETE or a stop ended it
inline constexpr const char* kRenderCancelled = "render_cancelled";  // 409: see RenderJob
inline constexpr const char* kRebuildCancelled = "rebuild_cancelled";  // 409: DELETE or a stop
inline constexpr const char* kTooManyConnections = "too_many_connections";  // 503 per address
inline constexpr const char* kRequestTimeout = "request_timeout";  // 408: a head too slow
inline constexpr const char* kHeadersTooLarge = "headers_too_large";  // 431
inline constexpr const char* kFrameTooCostly = "frame_too_costly";  // 422, names the limit
}  // namespace error_code

// Fixed bodies for when building one fails (no memory left, or a throwing error path).
inline constexpr const char* kInternalErrorBody =
    R"({"error":{"code":"internal_error","message":"internal error","path":""}})";
inline constexpr const char* kOutOfMemoryBody =
    R"({"error":{"code":"out_of_memory","message":"out of memory","path":""}})";

// Thrown by request handlers; the server turns it into status + errorJson.
class ApiError : public std::runtime_error {
 public:
  ApiError(int status, std::string code, std::string path, const std::string& message)
      : std::runtime_error(message),
        status_(status),
        code_(std::move(code)),
        path_(std::move(path)) {}
  int status() const { return status_; }
  const std::string& code() const { return code_; }
  const std::string& path() const { return path_; }

 private:
  int status_;
  std::string code_;
  std::string path_;
};

// {"error": {"code", "message", "path"}}; `extra` keys (e.g. "edit") are merged
// into the inner object.
nlohmann::json errorJson(const std::string& code, const std::string& message,
                         const std::string& path,
                         const nlohmann::json& extra = nlohmann::json::object());

// The body for a status that cpp-httplib produced itself (unknown path, oversized
// or unreadable body) and so has no handler-written body.
nlohmann::json errorJsonForStatus(int status, const std::string& method, const std::string& path,
                                  size_t maxBodyBytes);

}  // namespace penumbra::server
