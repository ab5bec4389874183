// Reading requests and writing responses for the HTTP handlers: JSON bodies, query
// parameters with key-path errors (`query.<name>`), JSON answers. Stateless; thread-safe.
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/geom/vec.h"
#include "server/api_errors.h"

namespace httplib {
struct Request;
struct Response;
}  // namespace httplib

namespace penumbra::server {

// JSON text that never throws on bad bytes: invalid UTF-8 in a string becomes U+FFFD.
std::string dumpJson(const nlohmann::json& value);

// Writes `body` as the JSON answer with `status`; never throws on bad bytes (dumpJson).
void sendJson(httplib::Response& res, int status, const nlohmann::json& body);
void sendError(httplib::Response& res, const ApiError& error,
               const nlohmann::json& extra = nlohmann::json::object());

// The request body as JSON: 400 naming the problem when empty, malformed or too deep.
nlohmann::json parseBody(const httplib::Request& req);

// Query parameters: absent → nullopt; present but not what we need → 400 naming `query.<name>`.
std::optional<std::string> queryText(const httplib::Request& req, const char* name);
std::optional<uint64_t> queryUnsigned(const httplib::Request& req, const char* name, uint64_t min,
                                      uint64_t max);
std::optional<double> queryNumber(const httplib::Request& req, const char* name);
std::optional<Vec3> queryVec3(const httplib::Request& req, const char* name);

// Logs and answers 500 for what a handler did not expect.
void sendInternalError(const httplib::Request& req, httplib::Response& res, const char* what);

// Wraps a handler: ApiError → its status; anything else → 500, never a crash.
template <typename Handler>
auto guarded(Handler handler) {
  return [handler](const httplib::Request& req, httplib::Response& res) {
    try {
      handler(req, res);
    } catch (const ApiError& error) {
      sendError(res, error);
    } catch (const std::exception& error) {
      sendInternalError(req, res, error.what());
    } catch (...) {
      sendInternalError(req, res, "unknown exception");
    }
  };
}

}  // namespace penumbra::server
