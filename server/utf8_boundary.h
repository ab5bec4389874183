// Invalid UTF-8 at the HTTP boundary (docs/API.md "Text encoding"): what a request carries
// outside a JSON body (query, form parts) and what an imported file names is checked here and
// refused with 400 `invalid_utf8` naming where it was. Stateless; thread-safe.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "core/scene/scene.h"
#include "protocol/utf8.h"

namespace httplib {
struct Request;
}

namespace penumbra::server {

using protocol::isValidUtf8;

// Throws ApiError 400 `invalid_utf8` for the first query parameter (name or value:
// `query.<name>`) or form part (name, file name, content type: `(form).<part>.filename`, ...)
// that is not valid UTF-8.
void requireUtf8Request(const httplib::Request& req);

// The key path of the first id in `scene` (lights, materials, objects and their material
// names) that is not valid UTF-8, e.g. "objects[3].id"; nullopt if all are.
std::optional<std::string> invalidUtf8Path(const Scene& scene);

}  // namespace penumbra::server
