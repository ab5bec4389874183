// Answers whose body is written as it is made: chunked transfer (gzip when the client takes
// it, as httplib does for any text), so a large body is never whole in memory (the mesh JSON of
// sparse 1,500 cubes is 106 MB of text, and was ~640 MB as a document).
#pragma once

#include <functional>
#include <iosfwd>

#include <httplib.h>

namespace penumbra::server {

// Sets `res` to a 200 of `contentType` whose body `write` makes when the answer is sent, after
// the handler has returned: `write` must own (capture by value) what it reads. It writes to the
// socket in 64 KiB chunks; if the client goes away or `write` throws, the connection is closed
// (the status line is out by then, so a failure cannot become an error answer).
void sendStreamed(httplib::Response& res, const char* contentType, std::function<void(std::ostream&)> write);

}  // namespace penumbra::server
