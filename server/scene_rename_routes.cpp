// PATCH /api/scenes/{id}: a new name for a served scene ({"name": "…"}), journaled so a restart
// keeps it. The version does not move: a name is not an edit of the scene.
#include <httplib.h>

#include <nlohmann/json.hpp>
#include <string>

#include "server/body_reader.h"
#include "server/http_server.h"
#include "server/request_io.h"
#include "server/response_json.h"

namespace penumbra::server {

using nlohmann::json;

namespace {

constexpr size_t kMaxNameCharacters = 200;

// The body's "name", or 422 `invalid_name` naming the key path and what is wrong with it.
std::string nameOf(const json& body) {
  const auto refuse = [](const std::string& path, const std::string& problem) {
    return ApiError(422, error_code::kInvalidName, path, problem);
  };
  if (!body.is_object()) throw refuse("", "the body must be an object {\"name\": \"…\"}");
  const auto it = body.find("name");
  if (it == body.end()) throw refuse("name", "missing");
  if (!it->is_string()) throw refuse("name", "must be a string");
  const std::string name = it->get<std::string>();
  size_t characters = 0;
  bool blank = true;
  for (const unsigned char c : name) {
    if ((c & 0xC0) != 0x80) ++characters;  // UTF-8 (parseBody checked it): count lead bytes
    if (c < 0x20 || c == 0x7F) throw refuse("name", "contains a control character");
    if (c != ' ') blank = false;
  }
  if (blank) throw refuse("name", "is empty");
  if (characters > kMaxNameCharacters)
    throw refuse("name", "is longer than " + std::to_string(kMaxNameCharacters) + " characters");
  return name;
}

}  // namespace

void HttpServer::registerRenameRoutes() {
  const std::string scenePath = std::string("/api/scenes/") + kIdPattern;
  http_->Patch(
      scenePath, readingBody(options_.maxBodyBytes, guarded([this](const httplib::Request& req,
                                                                   httplib::Response& res) {
        const auto session = findScene(req.matches[1]);
        refuseIfStalled(*session);  // read-only until repaired, its name included
        const std::string name = nameOf(parseBody(req));
        session->rename(name, [&] {
          if (!journal_) return;
          int64_t key = 0;
          {
            std::lock_guard lock(scenesMutex_);
            const auto it = journalKeys_.find(session.get());
            if (it == journalKeys_.end()) return;  // a concurrent DELETE took it
            key = it->second;
          }
          try {
            journal_->renameScene(key, name);
          } catch (const LeaseLost& error) {  // another node took the scene over
            dropScene(session->id(), error.what());
            throw ApiError(503, error_code::kOwnedElsewhere, "id",
                           std::string(error.what()) + "; the scene keeps its name, retry");
          } catch (const std::exception& error) {
            throw ApiError(503, error_code::kJournalFailed, "",
                           std::string("the journal could not record the name (") + error.what() +
                               "); the scene keeps its name");
          }
        });
        sendJson(res, 200, sceneSummaryJson(*session->snapshot()));
      })));
}

}  // namespace penumbra::server
