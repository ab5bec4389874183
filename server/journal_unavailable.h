// The journal cannot be reached or written durably now (its database's connection lost, the
// database frozen or stopped, the data directory gone): whatever request needed it is answered
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
