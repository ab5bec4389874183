// A look at the journal's write-ahead log before SQLite opens it (docs/SERVER.md "Durability").
// SQLite replays a WAL up to its first frame whose checksum fails and silently ignores the rest,
// committed transactions included; this reads the file the same way and reports such ignored
// frames of the current log (their salts match the header's), so damage is loud, never silent.
// Free function of a file; thread-safe.
#pragma once

#include <string>

namespace penumbra::server {

// Empty when `walPath` is missing or empty, or no committed transaction of its current log lies
// past the first frame that fails SQLite's checksum chain (a kill -9 leaves at most an incomplete,
// unacknowledged last transaction); else what is lost, in words.
std::string walProblem(const std::string& walPath);

}  // namespace penumbra::server
