// The page around a benchmark report: one style sheet, the title as <h1>, the body, and
// the numbers as JSON at the end (self-contained: no scripts, no external resources).
// Pure function; thread-safe.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace penumbra::bench {

// `body` is HTML; `title` is text (escaped here).
std::string htmlPage(const std::string& title, const std::string& body,
                     const nlohmann::json& numbers);

}  // namespace penumbra::bench
