#include "server/request_io.h"

#include <httplib.h>

#include <charconv>
#include <cmath>

#include "protocol/json_reader.h"
#include "protocol/json_text.h"
#include "protocol/validation_error.h"
#include "server/json_error_path.h"
#include "server/limits.h"

namespace penumbra::server {

using nlohmann::json;

std::string jsonText(const json& value) {
  return value.dump(-1, ' ', false, json::error_handler_t::replace);
}

void sendJson(httplib::Response& res, int status, const json& body) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(jsonText(body), "application/json");
}

void sendError(httplib::Response& res, const ApiError& error, const json& extra) {
  sendJson(res, error.status(), errorJson(error.code(), error.what(), error.path(), extra));
  if (error.code() == error_code::kRestoring || error.code() == error_code::kBuilding ||
      error.code() == error_code::kOwnedElsewhere)
    res.set_header("Retry-After", "1");
}

// Request bodies: size was checked by httplib (413); here syntax and depth.
void sendBusy(httplib::Response& res, const std::string& why) {
  sendError(res, ApiError(503, error_code::kBusy, "", why + "; retry after 1 s"));
  res.set_header("Retry-After", "1");
}

void setMeshToleranceHeader(httplib::Response& res, double tolerance) {
  res.set_header("X-Penumbra-Mesh-Tolerance", json(tolerance).dump());
}

json parseBody(const httplib::Request& req) {
  if (req.body.empty())
    throw ApiError(400, error_code::kMalformedJson, "(json)",
                   "the request body is empty; send a JSON document");
  try {
    // (the server's --max-body-mib may exceed the default)
    return protocol::parseJsonText(req.body, req.body.size(), protocol::kMaxJsonDepth);
  } catch (const protocol::ValidationError& error) {
    // nlohmann refuses ill-formed UTF-8 in strings and keys; say where it was.
    if (error.problem().find("UTF-8") != std::string::npos)
      throw ApiError(400, error_code::kInvalidUtf8, jsonErrorPath(req.body),
                     "a string or key is not valid UTF-8 (" + error.problem() + ")");
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

void sendInternalError(const httplib::Request& req, httplib::Response& res, const char* what,
                       bool outOfMemory) noexcept {
  std::fprintf(stderr, "penumbra serve: %s on %s %s: %s\n",
               outOfMemory ? "out of memory" : "internal error", req.method.c_str(),
               req.path.c_str(), what);
  const int status = outOfMemory ? 507 : 500;
  try {
    sendJson(
        res, status,
        errorJson(outOfMemory ? error_code::kOutOfMemory : error_code::kInternal,
                  std::string(outOfMemory ? "out of memory: " : "internal error: ") + what, ""));
  } catch (...) {  // e.g. no memory for the body: a fixed one
    res.status = status;
    res.set_content(outOfMemory ? kOutOfMemoryBody : kInternalErrorBody, "application/json");
  }
}

}  // namespace penumbra::server
