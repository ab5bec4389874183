#include "server/api_errors.h"

namespace penumbra::server {

nlohmann::json errorJson(const std::string& code, const std::string& message,
                         const std::string& path, const nlohmann::json& extra) {
  nlohmann::json inner = {{"code", code}, {"message", message}, {"path", path}};
  for (const auto& [key, value] : extra.items()) inner[key] = value;
  return {{"error", std::move(inner)}};
}

nlohmann::json errorJsonForStatus(int status, const std::string& method, const std::string& path,
                                  size_t maxBodyBytes) {
  switch (status) {
    case 404:
      return errorJson(error_code::kNotFound, "no such resource: " + method + " " + path, "(url)");
    case 413:
      return errorJson(
          error_code::kPayloadTooLarge,
          "request body is larger than the limit of " + std::to_string(maxBodyBytes) +
              " bytes (the server's --max-body-mib)",
          "(body)");
    case 400:
      return errorJson(error_code::kBadRequest, "the request could not be read", "(request)");
    default:
      if (status >= 500)
        return errorJson(error_code::kInternal,
                         "internal error (HTTP " + std::to_string(status) + ")", "");
      return errorJson(error_code::kBadRequest,
                       "request refused (HTTP " + std::to_string(status) + ")", "(request)");
  }
}

}  // namespace penumbra::server
