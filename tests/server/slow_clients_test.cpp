// Slow clients cannot starve the server: 500 sockets that send half a request and wait (a
// slowloris) each hold a worker, and /api/health still answers at once, because the pool starts
// a thread per connection when none is idle (ElasticPool). With httplib's fixed pool of 128,
// 130 such sockets blocked every later request.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "server/elastic_pool.h"
#include "tests/server/server_fixture.h"

namespace penumbra::server::test {
namespace {

// Opens a connection and sends a request head without its final blank line.
int halfRequest(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(uint16_t(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (fd < 0 || connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    if (fd >= 0) close(fd);
    return -1;
  }
  const char head[] = "GET /api/health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ";
  (void)!write(fd, head, sizeof head - 1);
  return fd;
}

// Both ends of every socket live in this process: as many as the descriptor limit allows.
int slowSocketsAllowed(int wanted) {
  rlimit limit{};
  getrlimit(RLIMIT_NOFILE, &limit);
  limit.rlim_cur = std::max<rlim_t>(limit.rlim_cur, std::min<rlim_t>(limit.rlim_max, 4096));
  setrlimit(RLIMIT_NOFILE, &limit);
  getrlimit(RLIMIT_NOFILE, &limit);
  return std::min<int>(wanted, int((limit.rlim_cur - 200) / 2));
}

TEST(SlowClients, HealthAnswersWhile500SocketsHoldHalfARequest) {
  const int count = slowSocketsAllowed(500);
  ASSERT_GE(count, 300) << "raise the open-file limit";
  // All from one address here: the cap per address (ConnectionLimits test) is lifted, so every
  // socket holds a worker.
  ServerOptions options = RunningServer::loopback();
  options.connections.perAddress = 1000;
  RunningServer running(options);
  std::vector<int> sockets;
  for (int i = 0; i < count; ++i) {
    const int fd = halfRequest(running.port());
    ASSERT_GE(fd, 0) << "socket " << i;
    sockets.push_back(fd);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // every one reached a worker
  auto client = running.client();
  client.set_read_timeout(time_t(5 * kTimingSlowdown), 0);
  for (int i = 0; i < 5; ++i) {
    const auto start = std::chrono::steady_clock::now();
    const auto health = client.Get("/api/health");
    ASSERT_TRUE(health) << "no answer with " << count << " slow sockets open";
    EXPECT_EQ(health->status, 200);
    EXPECT_LT(std::chrono::steady_clock::now() - start, timingBound(2));
  }
  for (const int fd : sockets) close(fd);
}

TEST(ElasticPool, GrowsPerWaitingTaskAndShrinksBackWhenIdle) {
  ElasticPool pool(2, 64, 1);
  EXPECT_EQ(pool.threads(), 2u);
  std::atomic<int> running{0};
  std::atomic<bool> release{false};
  for (int i = 0; i < 40; ++i)
    pool.enqueue([&] {
      ++running;
      while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    });
  // Every task runs at once: none waits behind another.
  for (int i = 0; i < 2000 && running < 40; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_EQ(running, 40);
  EXPECT_GE(pool.threads(), 40u);
  release = true;
  for (int i = 0; i < 400 && pool.threads() > 2; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(pool.threads(), 2u);  // back to the minimum after 1 s idle
  // At the maximum, tasks wait for a thread instead of failing.
  ElasticPool small(1, 2, 1);
  std::atomic<int> done{0};
  for (int i = 0; i < 10; ++i) small.enqueue([&] { ++done; });
  small.shutdown();  // runs what is queued
  EXPECT_EQ(done, 10);
  EXPECT_LE(small.threads(), 2u);
}

}  // namespace
}  // namespace penumbra::server::test
