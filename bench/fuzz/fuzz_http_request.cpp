// Fuzz target: raw HTTP request bytes sent over loopback to the project's HttpServer (every
// route, the static page from web_client/), started once per process and serving the tiny
// scene as "s". After each input the server is put back as it was (scenes it created deleted,
// "s" at version 0), so an input replays the same way. A finding: the server dies (the
// process aborts) or a sanitizer report; with PENUMBRA_FUZZ_STRICT=1 also a 500 answer.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <httplib.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstddef>
#include <cstdint>
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
    port_ = server_.bind();
    server_.addScene(fuzz::tinyScene(), "tiny", "s");
    listener_ = std::thread([this] { server_.listen(); });
    while (!server_.isRunning()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  // Never destroyed (stopping at exit races libFuzzer's own exit path); the OS reclaims it.

  int port() const { return port_; }

  // Deletes every scene but "s", and serves "s" afresh if a request changed it.
  void reset() {
    httplib::Client client("127.0.0.1", port_);
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
    return o;
  }

  server::HttpServer server_;
  int port_ = 0;
  std::thread listener_;
};

FuzzServer& fuzzServer() {
  static FuzzServer* server = new FuzzServer();  // see ~FuzzServer
  return *server;
}

// Sends the bytes, half-closes, and reads the answer until the server closes (at most ~2 s).
// An event stream stays open: its answer is read for 50 ms after its headers (its first event),
// not 2 s. (The target's ~60 executions a second come mostly from re-meshing the tiny scene.)
std::string exchange(int port, const uint8_t* data, size_t size) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  fuzz::check(fd >= 0, "socket() failed");
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(uint16_t(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  fuzz::check(::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0, "server not accepting");
  timeval timeout{0, 200 * 1000};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
  for (size_t sent = 0; sent < size;) {
    const ssize_t n = ::send(fd, data + sent, size - sent, MSG_NOSIGNAL);
    if (n <= 0) break;  // the server may answer (413, 400) and close before reading it all
    sent += size_t(n);
  }
  ::shutdown(fd, SHUT_WR);
  std::string answer;
  char buffer[16384];
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  bool stream = false;
  while (std::chrono::steady_clock::now() < deadline) {
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) continue;
      break;
    }
    answer.append(buffer, size_t(n));
    const size_t headersEnd = answer.find("\r\n\r\n");
    if (!stream && headersEnd != std::string::npos &&
        answer.substr(0, headersEnd).find("text/event-stream") != std::string::npos) {
      stream = true;
      deadline = std::min(deadline, std::chrono::steady_clock::now() + std::chrono::milliseconds(50));
    }
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
