#include "server/body_reader.h"

#include <httplib.h>

#include <string>

#include "server/api_errors.h"
#include "server/request_io.h"

namespace penumbra::server {

namespace {

// Counts decoded bytes over all parts. Past the limit nothing more is kept, but the body is still
// read (and dropped) up to kDrainBytes more, so that a client which sends its whole body before
// reading hears the 413 instead of a reset connection; beyond that, reading stops.
constexpr size_t kDrainBytes = size_t(64) << 20;

struct BodyBudget {
  size_t maxBytes;
  size_t seen = 0;
  bool exceeded() const { return seen > maxBytes; }
  // False: stop reading. Else whether to keep these bytes.
  bool read(size_t n, bool& keep) {
    seen += n;
    keep = !exceeded();
    return keep || seen - maxBytes <= kDrainBytes;
  }
};

ApiError tooLarge(size_t maxBytes) {
  return ApiError(413, error_code::kPayloadTooLarge, "(body)",
                  "request body is larger than the limit of " + std::to_string(maxBytes) +
                      " bytes after decoding (the server's --max-body-mib)");
}

// Reads the body into req.body / req.files (httplib's routing owns the Request, not const).
bool readBody(const httplib::Request& req, const httplib::ContentReader& reader,
              BodyBudget& budget) {
  auto& request = const_cast<httplib::Request&>(req);
  if (!req.is_multipart_form_data())
    return reader([&](const char* data, size_t n) {
      bool keep = false;
      if (!budget.read(n, keep)) return false;
      if (keep) request.body.append(data, n);
      return true;
    });
  httplib::MultipartFormData* part = nullptr;
  return reader(
      [&](const httplib::MultipartFormData& header) {
        part = &request.files.emplace(header.name, header)->second;
        return true;
      },
      [&](const char* data, size_t n) {
        bool keep = false;
        if (!budget.read(n, keep) || !part) return false;
        if (keep) part->content.append(data, n);
        return true;
      });
}

}  // namespace

BodyReadingHandler readingBody(size_t maxBytes, BodyHandler handler) {
  return
      [maxBytes, handler = std::move(handler)](const httplib::Request& req, httplib::Response& res,
                                               const httplib::ContentReader& reader) noexcept {
        try {
          BodyBudget budget{maxBytes};
          const bool read = readBody(req, reader, budget);
          // httplib refuses a Content-Length over its limit itself (413, the body skipped).
          if (budget.exceeded() || res.status == 413) {
            if (!read) res.set_header("Connection", "close");  // the rest is still on the wire
            throw tooLarge(maxBytes);
          }
          if (!read) {
            res.set_header("Connection", "close");
            throw ApiError(400, error_code::kBadRequest, "(body)",
                           "the request body could not be read (cut short, or an encoding that "
                           "does not decode)");
          }
        } catch (const ApiError& error) {
          try {
            sendError(res, error);
          } catch (...) {
            sendInternalError(req, res, "cannot write the error", true);
          }
          return;
        } catch (...) {
          sendInternalError(req, res, "the request body could not be read", true);
          return;
        }
        handler(req, res);
      };
}

}  // namespace penumbra::server
