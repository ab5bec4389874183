// Who may do what (docs/SERVER.md "Access"): the bearer token on every mutating request; pages of
// other origins never mutate (Origin checked; issue 36, item 6), a loopback server answers only
// requests naming a loopback host (Host checked: DNS rebinding); static files only from inside
// their mounted folder (no "..", no symlink leading out). No CORS headers are ever sent.
#include <httplib.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "server/http_server.h"
#include "server/request_io.h"

namespace penumbra::server {

namespace {

namespace fs = std::filesystem;

bool isMutating(const std::string& method) {
  return method == "POST" || method == "PUT" || method == "PATCH" || method == "DELETE";
}

// Compares in time independent of where the strings first differ.
bool sameSecret(const std::string& given, const std::string& expected) {
  unsigned char diff = given.size() == expected.size() ? 0 : 1;
  for (size_t i = 0; i < given.size(); ++i)
    diff |= static_cast<unsigned char>(given[i] ^ expected[i % expected.size()]);
  return diff == 0;
}

// Whether `root`/`sub` (root canonical) names something inside root once "..", "." and
// symlinks are resolved.
bool staysInside(const fs::path& root, const std::string& sub) {
  std::error_code error;
  const fs::path resolved = fs::weakly_canonical(root / fs::path(sub).relative_path(), error);
  if (error) return false;
  const auto [rootEnd, resolvedAt] =
      std::mismatch(root.begin(), root.end(), resolved.begin(), resolved.end());
  return rootEnd == root.end();
}

std::string lowered(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The host of an authority "name", "name:port" or "[v6]:port", lower-cased, brackets kept off.
std::string hostOf(const std::string& authority) {
  const std::string a = lowered(authority);
  if (!a.empty() && a[0] == '[') return a.substr(1, a.find(']') == std::string::npos ? std::string::npos : a.find(']') - 1);
  return a.substr(0, a.find(':'));
}

// The authority of an origin "scheme://authority" (empty when it is not one, e.g. "null").
std::string authorityOf(const std::string& origin) {
  const size_t at = origin.find("://");
  return at == std::string::npos ? std::string() : lowered(origin.substr(at + 3));
}

}  // namespace

bool HttpServer::refuseForeignOrigin(const httplib::Request& req, httplib::Response& res) const {
  const std::string host = req.get_header_value("Host");
  const bool allowedHost = std::any_of(options_.allowedOrigins.begin(), options_.allowedOrigins.end(),
                                       [&](const std::string& o) { return hostOf(authorityOf(o)) == hostOf(host); });
  if (isLoopbackHost(options_.host) && !host.empty() && !isLoopbackHost(hostOf(host)) && !allowedHost) {
    sendJson(res, 403,
             errorJson(error_code::kForbiddenOrigin,
                       "this server listens on a loopback address and answers only requests naming a loopback host, "
                       "not '" + host + "' (a page could reach it through a name resolving to 127.0.0.1); open it as "
                       "http://127.0.0.1 or http://localhost, or allow that name's origin with --allow-origin",
                       "(header).Host"));
    return true;
  }
  const std::string origin = req.get_header_value("Origin");
  if (!isMutating(req.method) || origin.empty()) return false;  // not a browser's cross-site write
  const bool same = authorityOf(origin) == lowered(host) && !host.empty();
  const bool listed = std::any_of(options_.allowedOrigins.begin(), options_.allowedOrigins.end(),
                                  [&](const std::string& o) { return lowered(o) == lowered(origin); });
  if (same || listed) return false;
  sendJson(res, 403,
           errorJson(error_code::kForbiddenOrigin,
                     "a page from " + origin + " may not change this server's scenes (only its own page, or an "
                     "origin given with --allow-origin)",
                     "(header).Origin"));
  return true;
}

bool HttpServer::refuseAccess(const httplib::Request& req, httplib::Response& res) const {
  {
    if (!options_.token.empty() && isMutating(req.method) &&
        !sameSecret(req.get_header_value("Authorization"), "Bearer " + options_.token)) {
      res.set_header("WWW-Authenticate", "Bearer");
      sendJson(res, 401,
               errorJson(error_code::kUnauthorized,
                         "this server needs its token: send 'Authorization: Bearer TOKEN' "
                         "(the page takes it from ?token=)",
                         "(header).Authorization"));
      return true;
    }
    if ((req.method == "GET" || req.method == "HEAD") && req.path.rfind("/api/", 0) != 0) {
      // The mount this path falls under: the longest matching prefix (roots are canonical).
      const std::pair<std::string, std::string>* mount = nullptr;
      for (const auto& candidate : staticRoots_)
        if (req.path.rfind(candidate.first, 0) == 0 &&
            (!mount || candidate.first.size() > mount->first.size()))
          mount = &candidate;
      if (mount && (req.path.find('\\') != std::string::npos ||
                    !staysInside(mount->second, req.path.substr(mount->first.size())))) {
        sendJson(res, 404, errorJson(error_code::kNotFound, "no such file", "(url)"));
        return true;
      }
    }
    return false;
  }
}

}  // namespace penumbra::server
