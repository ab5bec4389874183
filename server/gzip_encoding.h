// gzip Content-Encoding for large binary responses (the mesh's typed arrays), which
// cpp-httplib does not compress itself (it only compresses text and JSON types).
// Free functions; thread-safe.
#pragma once

#include <string>
#include <string_view>

namespace penumbra::server {

// Whether an Accept-Encoding header value allows gzip (a "gzip" or "*" coding whose
// q is not 0).
bool acceptsGzip(std::string_view acceptEncoding);

// `data` as one gzip member (RFC 1952). Level 1 (fastest): a frame's mesh delta is
// compressed per request, so time matters more than the last few percent.
// Throws std::runtime_error if zlib fails.
std::string gzipCompress(std::string_view data, int level = 1);

}  // namespace penumbra::server
