#include "server/connection_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <string_view>
#include <thread>
#include <vector>

#include "core/engine/seconds_since.h"
#include "server/api_errors.h"
#include "server/request_io.h"

namespace penumbra::server {

namespace {

using Clock = std::chrono::steady_clock;
constexpr size_t kBufferBytes = 16 << 10;
constexpr int kStopPollMs = 100;  // how often a connection waiting for its next request checks
                                  // for a stop
// A connection past its address's cap may still ask for /api/health: its whole head within this
// many bytes and milliseconds of the accept.
constexpr size_t kHealthHeadBytes = 4096;
constexpr int kHealthHeadMs = 200;

std::string peerAddress(socket_t sock) {
  sockaddr_storage address{};
  socklen_t length = sizeof address;
  if (getpeername(sock, reinterpret_cast<sockaddr*>(&address), &length) != 0) return "";
  char text[INET6_ADDRSTRLEN] = {};
  if (address.ss_family == AF_INET)
    inet_ntop(AF_INET, &reinterpret_cast<sockaddr_in*>(&address)->sin_addr, text, sizeof text);
  else if (address.ss_family == AF_INET6)
    inet_ntop(AF_INET6, &reinterpret_cast<sockaddr_in6*>(&address)->sin6_addr, text, sizeof text);
  return text;
}

// A socket as httplib's Stream, with one read buffer for the whole connection (so bytes of a
// pipelined next request stay for it) and the limits on each request's head and body.
class ConnectionStream : public httplib::Stream {
 public:
  ConnectionStream(socket_t sock, const ConnectionLimits& limits, int readTimeoutMs,
                   int writeTimeoutMs)
      : sock_(sock),
        limits_(limits),
        readTimeoutMs_(readTimeoutMs),
        writeTimeoutMs_(writeTimeoutMs) {
    buffer_.resize(kBufferBytes);
  }

  // Waits up to `timeoutMs` for the next request's first byte (false: none came, the client
  // closed, or `stopping` turned true), then starts counting its head.
  template <class Stopping>
  bool nextRequest(int timeoutMs, const Stopping& stopping) {
    const auto deadline = Clock::now() + std::chrono::milliseconds(timeoutMs);
    while (!buffered()) {
      if (stopping() || Clock::now() >= deadline) return false;
      if (!fill(kStopPollMs)) {
        if (closed_) return false;
      }
    }
    inHead_ = true;
    headBytes_ = headLines_ = 0;
    last4_ = 0;
    started_ = Clock::now();
    bodyBytes_ = 0;
    problem_ = {};
    return true;
  }

  bool buffered() const { return begin_ < end_; }
  const ConnectionServer::HeadProblem& problem() const { return problem_; }

  // The client closed its end (bytes it sent before are still ours to read).
  bool peerClosed() const {
    if (closed_) return true;
    pollfd p{sock_, POLLIN | POLLRDHUP, 0};
    if (poll(&p, 1, 0) <= 0) return false;
    if (p.revents & (POLLRDHUP | POLLHUP | POLLERR)) return true;
    char byte;
    return (p.revents & POLLIN) && recv(sock_, &byte, 1, MSG_PEEK | MSG_DONTWAIT) == 0;
  }

  bool is_readable() const override { return buffered() || waitFor(POLLIN, readTimeoutMs_); }
  bool is_writable() const override { return waitFor(POLLOUT, writeTimeoutMs_) && !peerClosed(); }

  ssize_t read(char* ptr, size_t size) override {
    if (problem_.status) return -1;
    if (!buffered()) {
      const int wait = inHead_ ? std::min(readTimeoutMs_, headMsLeft()) : readTimeoutMs_;
      if (wait <= 0 || !fill(wait)) {
        if (inHead_ && !closed_ && headMsLeft() <= 0)
          refuse(408, error_code::kRequestTimeout,
                 "the request's head took longer than " + seconds(limits_.headSeconds) +
                     " s to arrive");
        return closed_ ? 0 : -1;
      }
    }
    size_t n = std::min(size, end_ - begin_);
    if (inHead_)
      n = headRead(n);
    else if (!bodyOnTime(n))
      return -1;
    std::copy(buffer_.data() + begin_, buffer_.data() + begin_ + n, ptr);
    begin_ += n;
    return ssize_t(n);
  }

  ssize_t write(const char* ptr, size_t size) override {
    if (!waitFor(POLLOUT, writeTimeoutMs_)) return -1;
    return send(sock_, ptr, size, MSG_NOSIGNAL);
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    sockaddr_storage address{};
    socklen_t length = sizeof address;
    ip = peerAddress(sock_);
    port = -1;
    if (getpeername(sock_, reinterpret_cast<sockaddr*>(&address), &length) == 0)
      port =
          ntohs(address.ss_family == AF_INET6 ? reinterpret_cast<sockaddr_in6*>(&address)->sin6_port
                                              : reinterpret_cast<sockaddr_in*>(&address)->sin_port);
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    sockaddr_storage address{};
    socklen_t length = sizeof address;
    ip.clear();
    port = -1;
    if (getsockname(sock_, reinterpret_cast<sockaddr*>(&address), &length) != 0) return;
    char text[INET6_ADDRSTRLEN] = {};
    if (address.ss_family == AF_INET) {
      const auto* in = reinterpret_cast<sockaddr_in*>(&address);
      inet_ntop(AF_INET, &in->sin_addr, text, sizeof text);
      port = ntohs(in->sin_port);
    } else if (address.ss_family == AF_INET6) {
      const auto* in = reinterpret_cast<sockaddr_in6*>(&address);
      inet_ntop(AF_INET6, &in->sin6_addr, text, sizeof text);
      port = ntohs(in->sin6_port);
    }
    ip = text;
  }
  socket_t socket() const override { return sock_; }

 private:
  static std::string seconds(double s) {
    std::string text = std::to_string(s);
    text.erase(text.find_last_not_of('0') + 1);
    if (!text.empty() && text.back() == '.') text.pop_back();
    return text;
  }

  int headMsLeft() const { return int(1000 * (limits_.headSeconds - secondsSince(started_))); }

  bool waitFor(short events, int timeoutMs) const {
    pollfd p{sock_, events, 0};
    return poll(&p, 1, std::max(0, timeoutMs)) > 0 && (p.revents & events);
  }

  // Reads what the socket has (waiting up to timeoutMs) into the empty buffer.
  bool fill(int timeoutMs) {
    if (closed_ || !waitFor(POLLIN, timeoutMs)) return false;
    const ssize_t n = recv(sock_, buffer_.data(), buffer_.size(), 0);
    if (n <= 0) {
      closed_ = true;
      return false;
    }
    begin_ = 0;
    end_ = size_t(n);
    return true;
  }

  // Of n buffered bytes, those up to the head's end (its blank line), counted against the
  // head's limits; the head ends there and the body starts.
  size_t headRead(size_t n) {
    for (size_t i = 0; i < n; ++i) {
      const char c = buffer_[begin_ + i];
      last4_ = (last4_ << 8) | uint8_t(c);
      ++headBytes_;
      if (c == '\n') ++headLines_;
      if (headBytes_ > limits_.maxHeadBytes || headLines_ > limits_.maxHeaderLines + 1) {
        refuse(431, error_code::kHeadersTooLarge,
               "the request's head (request line and headers) is larger than " +
                   std::to_string(limits_.maxHeadBytes) + " bytes or " +
                   std::to_string(limits_.maxHeaderLines) + " header lines");
        return i;  // what was within the limits; the next read fails
      }
      if ((last4_ & 0xffffffff) == 0x0d0a0d0a || (last4_ & 0xffff) == 0x0a0a) {
        inHead_ = false;
        started_ = Clock::now();
        return i + 1;
      }
    }
    return n;
  }

  // A body may take headSeconds plus a second per minBodyBytesPerSecond bytes.
  bool bodyOnTime(size_t n) {
    bodyBytes_ += n;
    const double allowed =
        limits_.headSeconds + double(bodyBytes_) / double(limits_.minBodyBytesPerSecond);
    return secondsSince(started_) <= allowed;
  }

  void refuse(int status, const char* code, const std::string& message) {
    problem_.status = status;
    problem_.body = jsonText(errorJson(code, message, "(request)"));
  }

  const socket_t sock_;
  const ConnectionLimits& limits_;
  const int readTimeoutMs_, writeTimeoutMs_;
  std::vector<char> buffer_;
  size_t begin_ = 0, end_ = 0;
  bool closed_ = false;
  bool inHead_ = false;
  size_t headBytes_ = 0, headLines_ = 0, bodyBytes_ = 0;
  uint32_t last4_ = 0;
  Clock::time_point started_ = Clock::now();
  ConnectionServer::HeadProblem problem_;
};

thread_local ConnectionStream* current = nullptr;

// Whether the connection's first request is a GET of /api/health whose whole head arrived within
// kHealthHeadMs (peeked, left for the request loop to read).
bool asksForHealthAtOnce(socket_t sock) {
  char head[kHealthHeadBytes];
  const auto deadline = Clock::now() + std::chrono::milliseconds(kHealthHeadMs);
  for (;;) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    pollfd p{sock, POLLIN, 0};
    if (left <= 0 || poll(&p, 1, int(left)) <= 0) return false;
    const ssize_t n = recv(sock, head, sizeof head, MSG_PEEK | MSG_DONTWAIT);
    if (n <= 0) return false;
    const std::string_view text(head, size_t(n));
    if (text.find("\r\n\r\n") != std::string_view::npos)
      return text.rfind("GET /api/health ", 0) == 0 || text.rfind("GET /api/health?", 0) == 0;
    if (size_t(n) == sizeof head) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));  // a head still coming
  }
}

// An answer written by the loop itself (no request was read, or its head could not be).
void writeRaw(socket_t sock, int status, const char* reason, const std::string& body, bool retry) {
  std::string text = "HTTP/1.1 " + std::to_string(status) + " " + reason +
                     "\r\nContent-Type: application/json\r\nConnection: close\r\n" +
                     (retry ? "Retry-After: 1\r\n" : "") +
                     "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
  (void)!send(sock, text.data(), text.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
}

// Closes after the client read our answer: a close with its unread bytes still queued would
// reset the connection and could lose the answer. Drains at most 200 ms and 256 KiB: a client
// that keeps sending (a huge head) is reset then.
void closeGently(socket_t sock) {
  shutdown(sock, SHUT_WR);
  char sink[4096];
  const auto deadline = Clock::now() + std::chrono::milliseconds(200);
  size_t drained = 0;
  pollfd p{sock, POLLIN, 0};
  for (ssize_t n = 1; n > 0 && drained < (256 << 10) && Clock::now() < deadline;) {
    if (poll(&p, 1, 50) <= 0) break;
    n = recv(sock, sink, sizeof sink, 0);
    drained += n > 0 ? size_t(n) : 0;
  }
  close(sock);
}

}  // namespace

bool ConnectionServer::clientGone() { return current && current->peerClosed(); }

std::function<bool()> ConnectionServer::clientGoneProbe() {
  ConnectionStream* stream = current;
  return [stream] { return stream && stream->peerClosed(); };
}

ConnectionServer::HeadProblem ConnectionServer::headProblem() {
  return current ? current->problem() : HeadProblem{};
}

size_t ConnectionServer::connectionsFrom(const std::string& address) const {
  std::lock_guard lock(mutex_);
  const auto it = open_.find(address);
  return it == open_.end() ? 0 : it->second;
}

bool ConnectionServer::takeSlot(const std::string& address, bool reserve) {
  std::lock_guard lock(mutex_);
  size_t& open = (reserve ? reserved_ : open_)[address];
  if (open >= (reserve ? limits_.healthReserve : limits_.perAddress)) {
    if (open == 0) (reserve ? reserved_ : open_).erase(address);
    return false;
  }
  ++open;
  return true;
}

void ConnectionServer::giveSlot(const std::string& address, bool reserve) {
  std::lock_guard lock(mutex_);
  auto& slots = reserve ? reserved_ : open_;
  if (--slots[address] == 0) slots.erase(address);
}

bool ConnectionServer::process_and_close_socket(socket_t sock) {
  const std::string address = peerAddress(sock);
  if (takeSlot(address, false)) {
    const bool ok = serve(sock, keep_alive_max_count_);
    giveSlot(address, false);
    return ok;
  }
  // Over the cap: a health check sent at once is still answered (one request, then closed), so
  // the address's own slow or idle sockets cannot lock its health checker out.
  if (takeSlot(address, true)) {
    const bool health = asksForHealthAtOnce(sock);
    const bool ok = health && serve(sock, 1);
    giveSlot(address, true);
    if (health) return ok;
  }
  writeRaw(sock, 503, "Service Unavailable",
           jsonText(errorJson(error_code::kTooManyConnections,
                              "already " + std::to_string(limits_.perAddress) +
                                  " connections open from " + address +
                                  "; close one first (or reuse it: keep-alive)",
                              "(connection)")),
           true);
  closeGently(sock);
  return false;
}

bool ConnectionServer::serve(socket_t sock, size_t requests) {
  ConnectionStream stream(sock, limits_, int(read_timeout_sec_ * 1000 + read_timeout_usec_ / 1000),
                          int(write_timeout_sec_ * 1000 + write_timeout_usec_ / 1000));
  const auto stopping = [this] { return svr_sock_ == INVALID_SOCKET; };
  bool ok = true;
  for (size_t left = requests; left > 0; --left) {
    if (!stream.nextRequest(int(keep_alive_timeout_sec_ * 1000), stopping)) break;
    bool connectionClosed = false;
    current = &stream;
    ok = process_request(stream, left == 1, connectionClosed, nullptr);
    current = nullptr;
    if (stream.problem().status) {  // httplib answered 400 in the headers (our error handler
                                    // made it this), or nothing for the request line
      if (!ok)
        writeRaw(
            sock, stream.problem().status,
            stream.problem().status == 408 ? "Request Timeout" : "Request Header Fields Too Large",
            stream.problem().body, false);
      closeGently(sock);
      return false;
    }
    if (!ok || connectionClosed) break;
  }
  if (stream.buffered()) {  // bytes of a request we will not answer
    closeGently(sock);
  } else {
    shutdown(sock, SHUT_RDWR);
    close(sock);
  }
  return ok;
}

}  // namespace penumbra::server
