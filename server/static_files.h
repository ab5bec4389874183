// The page's static files (docs/API.md "Static files"): each file read and gzip-compressed once
// per change (not per request), served with a content ETag and Cache-Control. Thread-safe.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace httplib {
struct Request;
struct Response;
}  // namespace httplib

namespace penumbra::server {

// One file as served: its bytes, their gzip (empty when not worth it) and the ETag of each.
struct StaticFile {
  std::string bytes;
  std::string gzip;
  std::string etag;      // "\"<64-bit content hash>\""
  std::string gzipEtag;  // the gzip representation's: "\"<hash>-gz\""
  std::string contentType;
  std::filesystem::file_time_type modified;
  uintmax_t size = 0;
};

// The Content-Type for a file name's extension (application/octet-stream when unknown).
std::string contentTypeFor(const std::filesystem::path& file);

class StaticFiles {
 public:
  // Files under `dir` served at URL prefix `prefix` ("/" or "/node_modules/"); the longest
  // matching prefix wins. `cacheControl` is that mount's Cache-Control value.
  void mount(std::string prefix, std::filesystem::path dir, std::string cacheControl);

  // Answers a GET/HEAD for a file (200, or 304 when If-None-Match names its ETag) and
  // returns true; false when no mounted file has that path. Paths leading out of a mount are
  // refused before this (HttpServer::refuseAccess).
  bool serve(const httplib::Request& req, httplib::Response& res);

  // The file as cached (read and compressed on first use or after it changed); null if none.
  std::shared_ptr<const StaticFile> file(const std::filesystem::path& path);

 private:
  struct Mount {
    std::string prefix;
    std::filesystem::path dir;
    std::string cacheControl;
  };
  std::vector<Mount> mounts_;
  std::mutex mutex_;  // guards cache_
  std::map<std::string, std::shared_ptr<const StaticFile>> cache_;
};

}  // namespace penumbra::server
