// Reading untrusted JSON text and files: size limit, depth limit, parse errors
// turned into ValidationError (path `(json)`). Free functions; thread-safe.
#pragma once

#include <cstddef>
#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace penumbra::protocol {

// Limits for scene and mesh files read from disk.
inline constexpr size_t kMaxJsonFileBytes = size_t(64) << 20;  // 64 MiB
// Deepest nesting of arrays/objects accepted. A scene needs 5 levels
// (root, objects, object, faces, face); the slack is for unknown keys.
inline constexpr int kMaxJsonDepth = 64;

// Parses text as one JSON document. Throws ValidationError (path `(json)`) if the
// text is longer than maxBytes, nests arrays/objects deeper than maxDepth, is not
// valid JSON (the message gives the byte position), or holds a number too large
// for a double.
nlohmann::json parseJsonText(std::string_view text, size_t maxBytes, int maxDepth);

// Reads a whole file. Throws ValidationError (path `(json)`) if it is larger than
// maxBytes (checked before reading), std::runtime_error if it cannot be read.
std::string readTextFile(const std::string& path, size_t maxBytes);
// Writes a whole file (replacing it). Throws std::runtime_error on failure.
void writeTextFile(const std::string& path, std::string_view text);
// The same for text written piece by piece by `write` (a mesh file is never one string).
void writeTextFileWith(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace penumbra::protocol
