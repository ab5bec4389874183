// cpp-httplib's server with a connection loop of our own (docs/API.md "Load", "A cap per client
// address"): at most `perAddress` connections from one client address (past it a 503 and close,
// unless one of a few more sends a whole GET /api/health at once: that is answered); each request's head (request line and headers) must arrive within
// `headSeconds` and stay within `maxHeadBytes` and `maxHeaderLines` (else 408 / 431 and close); a
// body must keep arriving at `minBodyBytesPerSecond` after its first `headSeconds`; pipelined
// requests are read from one buffer kept across requests and answered in order (httplib 0.11
// makes a new buffer per request and dropped them). Handlers ask clientGone() whether the client
// of the request they answer has closed its connection. Thread-safe; each connection on its
// worker.
#pragma once

#include <httplib.h>

#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <mutex>
#include <string>

namespace penumbra::server {

struct ConnectionLimits {
  size_t perAddress = 256;
  // Past the cap, this many more connections of an address may each ask for GET /api/health,
  // the whole head there within kHealthHeadMs of the accept (a health checker sends it at once);
  // anything else, or later, is the 503.
  size_t healthReserve = 8;
  double headSeconds = 10;
  size_t maxHeadBytes = 64 << 10;
  size_t maxHeaderLines = 128;
  size_t minBodyBytesPerSecond = 64 << 10;
};

class ConnectionServer : public httplib::Server {
 public:
  explicit ConnectionServer(ConnectionLimits limits) : limits_(limits) {}

  // Whether the client of the request this thread is answering has closed its connection
  // (false outside a request).
  static bool clientGone();
  // clientGone() for this thread's current request, callable from other threads while that
  // request is being answered (a render's worker threads); false outside a request.
  static std::function<bool()> clientGoneProbe();
  // Why the head of this thread's current request could not be read (for the error handler,
  // which sees only httplib's 400): 408 or 431 with its JSON error body; status 0 when none.
  struct HeadProblem {
    int status = 0;
    std::string body;
  };
  static HeadProblem headProblem();

  const ConnectionLimits& limits() const { return limits_; }
  size_t connectionsFrom(const std::string& address) const;

 private:
  bool process_and_close_socket(socket_t sock) override;
  // A slot of the address's cap (`reserve` false) or of its health reserve.
  bool takeSlot(const std::string& address, bool reserve);
  void giveSlot(const std::string& address, bool reserve);
  // Serves the connection's requests (its slot taken), at most `requests` of them.
  bool serve(socket_t sock, size_t requests);

  const ConnectionLimits limits_;
  mutable std::mutex mutex_;
  std::map<std::string, size_t> open_;  // client address → connections open, guarded by mutex_
  std::map<std::string, size_t> reserved_;  // client address → health reserve slots held
};

}  // namespace penumbra::server
