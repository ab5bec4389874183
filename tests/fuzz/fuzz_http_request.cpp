// Fuzz target: raw HTTP request bytes sent over loopback to the project's HttpServer (every
// route, the static page from web_client/), started once per process and serving the tiny
// scene as "s". After each input the server is put back as it was (scenes it created deleted,
// "s" at version 0), so an input replays the same way. A finding: the server dies (the
// process aborts) or a sanitizer report; with PENUMBRA_FUZZ_STRICT=1 also a 500 answer.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <httplib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <thread>

#include "fuzz_support.h"
#include "server/http_server.h"

using namespace penumbra;

namespace {

class FuzzServer {
 public:
  FuzzServer() : server_(options()) {
    ::setenv("PENUMBRA_IMAGE_MODULE", PENUMBRA_IMAGE_MODULE_PATH, 0);  // GET …/image encodes PNGs
    port_ = server_.bind();
    server_.addScene(fuzz::tinyScene(), "tiny", "s");
    listener_ = std::thread([this] { server_.listen(); });
    while (!server_.isRunning()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    control_ = std::make_unique<httplib::Client>("127.0.0.1", port_);
    control_->set_keep_alive(true);
  }
  // Never destroyed (stopping at exit races libFuzzer's own exit path); the OS reclaims it.

  int port() const { return port_; }

  // Deletes every scene but "s", and serves "s" afresh if a request changed it.
  void reset() {
    httplib::Client& client = *control_;  // one kept-alive connection, not a new one an input
    auto listed = client.Get("/api/scenes");
    fuzz::check(listed && listed->status == 200, "GET /api/scenes failed after an input");
    const auto scenes = nlohmann::json::parse(listed->body).at("scenes");
    bool haveBase = false;
    for (const auto& scene : scenes) {
      const std::string id = scene.at("id");
      if (id == "s" && scene.at("version") == 0) {
        haveBase = true;
        continue;
      }
      auto deleted = client.Delete("/api/scenes/" + id);
      fuzz::check(deleted && deleted->status / 100 == 2, "DELETE of a scene failed");
    }
    if (!haveBase) server_.addScene(fuzz::tinyScene(), "tiny", "s");
  }

 private:
  static server::ServerOptions options() {
    server::ServerOptions o;
    o.host = "127.0.0.1";
    o.port = 0;
    o.staticDir = PENUMBRA_SOURCE_DIR "/web_client";
    // A 1 m display lattice instead of the default 0.28 m (the scene's diagonal / 32): the same
    // code paths with a tenth of the cells to light, so an accepted edit, whose undoing costs a
    // fresh scene, takes ~6 ms here instead of ~50 ms (the lighting is edit_frame's to fuzz).
    o.engine.meshSpacing = 1.0;
    return o;
  }

  server::HttpServer server_;
  int port_ = 0;
  std::thread listener_;
  std::unique_ptr<httplib::Client> control_;
};

FuzzServer& fuzzServer() {
  static FuzzServer* server = new FuzzServer();  // see ~FuzzServer
  return *server;
}

// Where an answer whose bytes so far are `answer` ends (npos: read until the server closes), once
// its headers are in; `head`: the request was a HEAD. An event stream's end is its first event.
size_t answerEnd(const std::string& answer, size_t headersEnd, bool head) {
  std::string headers = answer.substr(0, headersEnd);
  for (char& c : headers) c = char(std::tolower(static_cast<unsigned char>(c)));
  const size_t bodyStart = headersEnd + 4;
  const int status = answer.size() > 12 ? std::atoi(answer.c_str() + 9) : 0;
  if (head || status == 204 || status == 304 || (status >= 100 && status < 200)) return bodyStart;
  if (headers.find("text/event-stream") != std::string::npos) {
    const size_t event = answer.find("\n\n", bodyStart);
    return event == std::string::npos ? std::string::npos - 1 : event + 2;
  }
  if (headers.find("transfer-encoding: chunked") != std::string::npos) {
    const size_t last = answer.find("\r\n0\r\n\r\n", headersEnd);
    return last == std::string::npos ? std::string::npos - 1 : last + 7;
  }
  const size_t length = headers.find("content-length:");
  if (length != std::string::npos) return bodyStart + std::strtoull(headers.c_str() + length + 15, nullptr, 10);
  return std::string::npos;
}

// Whether the bytes hold a whole request (headers, and as much body as Content-Length says or a
// last chunk; a POST without either is cut): the server answers it without waiting for more.
// A header counts only at the start of a line, as the server reads it; a mutated "…Content-
// Length: 9" inside another header's value made a cut request look whole (a 2 s wait).
bool wholeRequest(const std::string& request) {
  const size_t headersEnd = request.find("\r\n\r\n");
  if (headersEnd == std::string::npos) return false;
  std::string headers = request.substr(0, headersEnd + 2);
  for (char& c : headers) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (headers.find("\r\ntransfer-encoding:") != std::string::npos)
    return request.size() >= 5 && request.compare(request.size() - 5, 5, "0\r\n\r\n") == 0;
  const size_t length = headers.find("\r\ncontent-length:");
  if (length == std::string::npos)  // the body of a POST, PUT or PATCH without one ends at EOF
    return !(headers.rfind("post ", 0) == 0 || headers.rfind("put ", 0) == 0 || headers.rfind("patch ", 0) == 0);
  return request.size() - headersEnd - 4 >= std::strtoull(headers.c_str() + length + 17, nullptr, 10);
}

// connect() that outlasts signals: libFuzzer's timeout alarm (SIGALRM, no SA_RESTART) made a
// connect on a starved machine fail with EINTR, which a long run took for a dead server. The
// connection goes on after EINTR; wait until it is made, then read its outcome.
bool connectRetrying(int fd, const sockaddr_in& addr) {
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0) return true;
  if (errno != EINTR) return false;
  pollfd writable{fd, POLLOUT, 0};
  while (::poll(&writable, 1, 10000) < 0 && errno == EINTR) {
  }
  int error = 0;
  socklen_t length = sizeof error;
  if (::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length) != 0) return false;
  errno = error;
  return error == 0;
}

// Sends the bytes and reads the first answer (at most ~2 s): until its Content-Length, its last
// chunk, an event stream's first event, or the server closing. A cut request is half-closed (the
// server would wait for its rest), a whole one is not: the HTTP library writes no answer to a
// client it has seen half-close, so half-closing every request lost the answers of all but the
// fastest handlers (the handlers ran, but the writing of their answers went unfuzzed).
std::string exchange(int port, const uint8_t* data, size_t size) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  fuzz::check(fd >= 0, "socket() failed");
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(uint16_t(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  // Closed with a reset, not a FIN: at ~250 inputs a second, sockets left in TIME_WAIT for a
  // minute used up the ~28,000 ephemeral ports and connect() failed after ~12 minutes.
  const linger reset{1, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_LINGER, &reset, sizeof reset);
  if (!connectRetrying(fd, addr)) fuzz::fail(std::string("server not accepting: ") + std::strerror(errno));
  timeval timeout{0, 200 * 1000};
  ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
  for (size_t sent = 0; sent < size;) {
    const ssize_t n = ::send(fd, data + sent, size - sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // the server may answer (413, 400) and close before reading it all
    sent += size_t(n);
  }
  const std::string request(reinterpret_cast<const char*>(data), size);
  const bool head = request.rfind("HEAD ", 0) == 0;
  bool halfClosed = !wholeRequest(request);
  if (halfClosed) ::shutdown(fd, SHUT_WR);
  const auto start = std::chrono::steady_clock::now();
  auto deadline = start + std::chrono::seconds(2);
  std::string answer;
  size_t end = std::string::npos;
  char buffer[16384];
  while (answer.size() < end) {
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) break;
    pollfd readable{fd, POLLIN, 0};
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now);
    // No byte after 150 ms: the server is most likely still waiting for a request the check
    // above took for whole (its parser disagrees on some mangled header); half-closing ends
    // that wait. A handler slower than that (rare with the 1 m lattice) has run either way.
    if (!halfClosed && answer.empty() && now - start >= std::chrono::milliseconds(150)) {
      ::shutdown(fd, SHUT_WR);
      halfClosed = true;
    }
    const int slice = halfClosed || !answer.empty() ? int(wait.count()) : 10;
    if (::poll(&readable, 1, std::max(1, std::min(slice, int(wait.count())))) <= 0) continue;
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) continue;
      break;
    }
    answer.append(buffer, size_t(n));
    const size_t headersEnd = answer.find("\r\n\r\n");
    if (headersEnd == std::string::npos) continue;
    end = answerEnd(answer, headersEnd, head);
    // A stream whose first event is slow to come is read for 50 ms, not 2 s.
    if (end == std::string::npos - 1 && answer.find("text/event-stream") < headersEnd)
      deadline = std::min(deadline, std::chrono::steady_clock::now() + std::chrono::milliseconds(50));
  }
  ::close(fd);
  return answer;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 1 << 20) return 0;
  FuzzServer& server = fuzzServer();
  const std::string answer = exchange(server.port(), data, size);
  if (fuzz::strict() && answer.find(" 500 ") != std::string::npos && answer.find(" 500 ") < 16)
    fuzz::fail("HTTP 500: " + answer.substr(0, 600));
  fuzz::note("answer: " + answer.substr(0, answer.find('\r')));
  server.reset();
  return 0;
}
