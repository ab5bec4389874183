// Byte ranges a request may ask for (issue 36, item 4): cpp-httplib answers every range of a
// `Range` header, each a full copy of its part, so 200 ranges of "0-" built a 775 MB answer from
// a 676-byte request. At most kMaxRanges ranges, and, when there are several, each closed
// ("a-b") and apart from the others; anything else is refused with 416 and its error JSON
// (path "(header).Range") before any work. A single range of any form is fine (what browsers
// and players send). Free function; thread-safe.
#pragma once

#include <httplib.h>

namespace penumbra::server {

inline constexpr size_t kMaxRanges = 8;

// Whether the request's ranges were refused (the 416 answer is in `res`).
bool refuseHostileRanges(const httplib::Request& req, httplib::Response& res);

}  // namespace penumbra::server
