// Reading requests and writing responses for the HTTP handlers: JSON bodies, query
// parameters with key-path errors (`query.<name>`), JSON answers. Stateless; thread-safe.
#pragma once

#include <cstdint>
#include <cstdio>
#include <new>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/geom/vec.h"
#include "server/api_errors.h"
#include "server/journal_unavailable.h"
#include "server/utf8_boundary.h"

namespace httplib {
struct Request;
struct Response;
}  // namespace httplib

namespace penumbra::server {

// JSON text that never throws on bad bytes (invalid UTF-8 in a string becomes U+FFFD).
std::string jsonText(const nlohmann::json& value);

// Writes `body` as the JSON answer with `status`; never throws on bad bytes (invalid UTF-8
// in a string is replaced by U+FFFD).
void sendJson(httplib::Response& res, int status, const nlohmann::json& body);
void sendError(httplib::Response& res, const ApiError& error,
               const nlohmann::json& extra = nlohmann::json::object());

// The request body as JSON: 400 naming the problem when empty, malformed or too deep;
// 400 `invalid_utf8` naming the key path when a string or key is not valid UTF-8.
nlohmann::json parseBody(const httplib::Request& req);

// 503 `busy` with Retry-After: 1, saying `why` (a queue or budget that is full right now).
void sendBusy(httplib::Response& res, const std::string& why);

// X-Penumbra-Mesh-Tolerance: the interpolation bound the display mesh (and an image shaded
// from it) is refined to, relative to each light's local unshadowed level; 0: not refined.
void setMeshToleranceHeader(httplib::Response& res, double tolerance);

// Query parameters: absent → nullopt; present but not what we need → 400 naming `query.<name>`.
std::optional<std::string> queryText(const httplib::Request& req, const char* name);
std::optional<uint64_t> queryUnsigned(const httplib::Request& req, const char* name, uint64_t min,
                                      uint64_t max);
std::optional<double> queryNumber(const httplib::Request& req, const char* name);
std::optional<Vec3> queryVec3(const httplib::Request& req, const char* name);

// Logs and answers 500 for what a handler did not expect (507 `out_of_memory` when
// `outOfMemory`). Never throws.
void sendInternalError(const httplib::Request& req, httplib::Response& res, const char* what,
                       bool outOfMemory = false) noexcept;

// 503 `journal_failed` for a request that needed the journal while it could not be reached.
inline ApiError journalUnavailableError(const JournalUnavailable& error) {
  return ApiError(503, error_code::kJournalFailed, "",
                  std::string("the journal cannot be reached (") + error.what() +
                      "); nothing was applied, retry");
}

// Wraps a handler: query and form text that is not UTF-8 → 400 before it runs; ApiError →
// its status; the journal unreachable → 503; std::bad_alloc → 507; anything else → 500. Never
// throws, never a crash.
template <typename Handler>
auto guarded(Handler handler) {
  return [handler](const httplib::Request& req, httplib::Response& res) noexcept {
    try {
      requireUtf8Request(req);
      handler(req, res);
    } catch (const ApiError& error) {
      try {
        sendError(res, error);
      } catch (...) {
        sendInternalError(req, res, "cannot write the error", true);
      }
    } catch (const JournalUnavailable& error) {
      try {
        sendError(res, journalUnavailableError(error));
      } catch (...) {
        sendInternalError(req, res, "cannot write the error", true);
      }
    } catch (const std::bad_alloc&) {
      sendInternalError(req, res, "out of memory", true);
    } catch (const std::exception& error) {
      sendInternalError(req, res, error.what());
    } catch (...) {
      sendInternalError(req, res, "unknown exception");
    }
  };
}

// Wraps a streaming content provider, which httplib calls outside any handler's try:
// an exception (no memory) ends the stream instead of the server.
template <typename Provider>
auto guardedProvider(Provider provider) {
  return [provider](size_t offset, auto& sink) noexcept {
    try {
      return provider(offset, sink);
    } catch (...) {
      return false;
    }
  };
}

}  // namespace penumbra::server
