// Where in a JSON text parsing stopped, as a key path ("edits[0].id"): nlohmann's parse
// errors give only a byte offset. Stateless; thread-safe.
#pragma once

#include <string>
#include <string_view>

namespace penumbra::server {

// The key path of the value (or the object, for a bad key) being read where `text` stops
// being valid JSON; "" at the top level or if the text parses.
std::string jsonErrorPath(std::string_view text);

}  // namespace penumbra::server
