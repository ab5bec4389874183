#include "server/static_files.h"

#include <httplib.h>

#include <cstdio>
#include <fstream>
#include <iterator>

#include "server/gzip_encoding.h"

namespace penumbra::server {

namespace fs = std::filesystem;

namespace {

// Files above this are served uncached and uncompressed (the page's largest, three.js's
// modules, are ~1.3 MB).
constexpr uintmax_t kMaxCachedBytes = uintmax_t(32) << 20;

uint64_t fnv1a64(const std::string& bytes) {
  uint64_t hash = 1469598103934665603ull;
  for (unsigned char c : bytes) hash = (hash ^ c) * 1099511628211ull;
  return hash;
}

bool compressible(const std::string& type) {
  return type.rfind("text/", 0) == 0 || type == "application/json" || type == "image/svg+xml" ||
         type == "application/wasm" || type == "model/gltf+json";
}

// Whether an If-None-Match value lists `etag` (or is "*").
bool listsEtag(const std::string& ifNoneMatch, const std::string& etag) {
  if (ifNoneMatch.find('*') != std::string::npos) return true;
  size_t at = 0;
  while ((at = ifNoneMatch.find(etag, at)) != std::string::npos) {
    // "W/" prefixes are allowed (weak comparison, RFC 9110 13.1.2).
    const bool startOk = at == 0 || ifNoneMatch[at - 1] == ' ' || ifNoneMatch[at - 1] == ',' ||
                         ifNoneMatch[at - 1] == '/';
    if (startOk) return true;
    at += etag.size();
  }
  return false;
}

std::shared_ptr<StaticFile> readFile(const fs::path& path, fs::file_time_type modified,
                                     uintmax_t size) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return nullptr;
  auto file = std::make_shared<StaticFile>();
  file->bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  file->modified = modified;
  file->size = size;
  file->contentType = contentTypeFor(path);
  char hash[24];
  std::snprintf(hash, sizeof hash, "%016llx",
                static_cast<unsigned long long>(fnv1a64(file->bytes)));
  file->etag = std::string("\"") + hash + "\"";
  file->gzipEtag = std::string("\"") + hash + "-gz\"";
  // Once per file version, so the slowest level costs nothing per request.
  if (compressible(file->contentType) && file->bytes.size() > 256) {
    std::string gzip = gzipCompress(file->bytes, 9);
    if (gzip.size() < file->bytes.size()) file->gzip = std::move(gzip);
  }
  return file;
}

}  // namespace

std::string contentTypeFor(const fs::path& file) {
  static const std::map<std::string, std::string> types = {{".html", "text/html; charset=utf-8"},
                                                           {".js", "text/javascript"},
                                                           {".mjs", "text/javascript"},
                                                           {".css", "text/css; charset=utf-8"},
                                                           {".json", "application/json"},
                                                           {".map", "application/json"},
                                                           {".txt", "text/plain; charset=utf-8"},
                                                           {".md", "text/plain; charset=utf-8"},
                                                           {".svg", "image/svg+xml"},
                                                           {".png", "image/png"},
                                                           {".jpg", "image/jpeg"},
                                                           {".ico", "image/x-icon"},
                                                           {".glb", "model/gltf-binary"},
                                                           {".gltf", "model/gltf+json"},
                                                           {".wasm", "application/wasm"},
                                                           {".exr", "image/x-exr"}};
  const auto it = types.find(file.extension().string());
  return it == types.end() ? "application/octet-stream" : it->second;
}

void StaticFiles::mount(std::string prefix, fs::path dir, std::string cacheControl) {
  mounts_.push_back({std::move(prefix), std::move(dir), std::move(cacheControl)});
}

std::shared_ptr<const StaticFile> StaticFiles::file(const fs::path& path) {
  std::error_code error;
  if (!fs::is_regular_file(path, error)) return nullptr;
  const auto modified = fs::last_write_time(path, error);
  const uintmax_t size = fs::file_size(path, error);
  if (error) return nullptr;
  const std::string key = path.string();
  {
    std::lock_guard lock(mutex_);
    const auto it = cache_.find(key);
    if (it != cache_.end() && it->second->modified == modified && it->second->size == size)
      return it->second;
  }
  // Read and compress outside the lock; two first requests may both do it, the last one stays.
  std::shared_ptr<StaticFile> fresh = readFile(path, modified, size);
  if (!fresh) return nullptr;
  if (size <= kMaxCachedBytes) {
    std::lock_guard lock(mutex_);
    cache_[key] = fresh;
  }
  return fresh;
}

bool StaticFiles::serve(const httplib::Request& req, httplib::Response& res) {
  const Mount* mount = nullptr;
  for (const Mount& candidate : mounts_)
    if (req.path.rfind(candidate.prefix, 0) == 0 &&
        (!mount || candidate.prefix.size() > mount->prefix.size()))
      mount = &candidate;
  if (!mount) return false;
  std::string sub = req.path.substr(mount->prefix.size());
  if (sub.empty() || sub.back() == '/') sub += "index.html";
  fs::path path = mount->dir / fs::path(sub).relative_path();
  std::error_code error;
  if (fs::is_directory(path, error)) path /= "index.html";
  const std::shared_ptr<const StaticFile> file = this->file(path);
  if (!file) return false;

  const bool gzip = !file->gzip.empty() && acceptsGzip(req.get_header_value("Accept-Encoding"));
  // The body is final: httplib must not compress it again (it would, per request, for text/*).
  const_cast<httplib::Request&>(req).headers.erase("Accept-Encoding");
  const std::string& etag = gzip ? file->gzipEtag : file->etag;
  res.set_header("ETag", etag);
  res.set_header("Cache-Control", mount->cacheControl);
  res.set_header("Vary", "Accept-Encoding");
  const std::string ifNoneMatch = req.get_header_value("If-None-Match");
  if (!ifNoneMatch.empty() &&
      (listsEtag(ifNoneMatch, file->etag) || listsEtag(ifNoneMatch, file->gzipEtag))) {
    res.status = 304;
    return true;
  }
  if (gzip) res.set_header("Content-Encoding", "gzip");
  res.set_content(gzip ? file->gzip : file->bytes, file->contentType);
  res.status = 200;
  return true;
}

}  // namespace penumbra::server
