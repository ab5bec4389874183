// The journal cannot be reached or written durably now (its database's connection lost, the
// database frozen or stopped, a statement cut by its timeout, the journal file locked by another
// writer, the data directory gone). Thrown by the journal's reachability checks and by both
// database wrappers (postgres_statements.h, sqlite_db.h), never for a statement the database
// refuses for what it says. Whatever request needed the journal is answered
// 503 `journal_failed` with nothing applied, never 500 (request_io.h's guarded, the server's
// exception handler, the edit route).
#pragma once

#include <stdexcept>

namespace penumbra::server {

class JournalUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace penumbra::server
