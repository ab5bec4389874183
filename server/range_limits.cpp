#include "server/range_limits.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "server/api_errors.h"
#include "server/request_io.h"

namespace penumbra::server {

namespace {

// Several ranges are fine only closed and disjoint: an open one ("a-", "-n") reaches the end,
// so two of them, or one beside any other, may cover the same bytes.
bool acceptable(const httplib::Ranges& ranges) {
  if (ranges.size() <= 1) return true;
  if (ranges.size() > kMaxRanges) return false;
  std::vector<std::pair<ssize_t, ssize_t>> closed(ranges.begin(), ranges.end());
  if (std::any_of(closed.begin(), closed.end(), [](const auto& r) { return r.first < 0 || r.second < r.first; }))
    return false;
  std::sort(closed.begin(), closed.end());
  for (size_t i = 1; i < closed.size(); ++i)
    if (closed[i].first <= closed[i - 1].second) return false;
  return true;
}

}  // namespace

bool refuseHostileRanges(const httplib::Request& req, httplib::Response& res) {
  if (acceptable(req.ranges)) return false;
  const std::string count = std::to_string(req.ranges.size());
  // cpp-httplib cuts any answer into the request's ranges, a 416's body too (200 empty parts
  // are still 41 kB of part headers): the ranges go. The pre-routing handler sees the request
  // as const, but it is cpp-httplib's own non-const object for this request.
  const_cast<httplib::Request&>(req).ranges.clear();
  sendJson(res, 416,
           errorJson(error_code::kBadRequest,
                     "Range asks for " + count + " ranges; this server answers one range, or up to " +
                         std::to_string(kMaxRanges) + " closed ones that do not overlap",
                     "(header).Range"));
  res.set_header("Content-Range", "bytes */*");
  return true;
}

}  // namespace penumbra::server
