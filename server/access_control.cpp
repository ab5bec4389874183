// Who may do what (README "HTTP server"): the bearer token on every mutating request, and static
// files only from inside their mounted folder (no "..", no symlink leading out).
#include <httplib.h>

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

}  // namespace

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
