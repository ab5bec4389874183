// Reading a request body with its size checked after decoding: httplib checks its body limit
// against Content-Length only, so a gzip body (1 MB on the wire, 2 GB inflated) or a chunked
// one (no length at all) was read whole. Routes that take a body read it through here instead:
// the decoded bytes (gzip inflated, chunks joined, form parts split) are counted as they
// arrive, and past the limit the read stops with 413 `payload_too_large` naming `(body)`.
#pragma once

#include <cstddef>
#include <functional>

namespace httplib {
struct Request;
struct Response;
class ContentReader;
}  // namespace httplib

namespace penumbra::server {

using BodyHandler = std::function<void(const httplib::Request&, httplib::Response&)>;
using BodyReadingHandler =
    std::function<void(const httplib::Request&, httplib::Response&, const httplib::ContentReader&)>;

// A handler for httplib's content-reader routes: reads the body (at most `maxBytes` decoded
// bytes) into req.body, or req.files for multipart/form-data, then calls `handler` (which sees
// the request as a plain route would). Over the limit: 413 and the connection is closed;
// unreadable: 400. Never throws.
BodyReadingHandler readingBody(size_t maxBytes, BodyHandler handler);

}  // namespace penumbra::server
