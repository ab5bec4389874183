// EditScheduler: one frame at a time, clients take turns (round-robin), a full queue refuses.
// Threads stand in for request workers; the order of grants is checked exactly.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "server/edit_scheduler.h"

namespace penumbra::server {
namespace {

void waitUntilQueued(const EditScheduler& scheduler, size_t n) {
  for (int i = 0; i < 5000 && scheduler.queued() != n; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ASSERT_EQ(scheduler.queued(), n);
}

TEST(EditScheduler, ClientsTakeTurnsInArrivalOrder) {
  EditScheduler scheduler(16);
  std::mutex mutex;
  std::vector<std::string> order;
  std::vector<std::thread> threads;
  {
    EditScheduler::Turn holding = scheduler.wait("first");
    // A sends three frames, then B one, then C two, while "first" holds the turn.
    size_t queued = 0;
    for (const char* client : {"A", "A", "A", "B", "C", "C"}) {
      threads.emplace_back([&, client] {
        EditScheduler::Turn turn = scheduler.wait(client);
        std::lock_guard lock(mutex);
        order.push_back(client);
      });
      waitUntilQueued(scheduler, ++queued);
    }
  }
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(order, (std::vector<std::string>{"A", "B", "C", "A", "C", "A"}));
  EXPECT_EQ(scheduler.queued(), 0u);
}

TEST(EditScheduler, FullQueueRefusesAndRecovers) {
  EditScheduler scheduler(2);
  std::vector<std::thread> threads;
  {
    EditScheduler::Turn holding = scheduler.wait("x");
    for (int i = 0; i < 2; ++i) {
      threads.emplace_back([&] { EditScheduler::Turn turn = scheduler.wait("y"); });
      waitUntilQueued(scheduler, size_t(i + 1));
    }
    EXPECT_THROW(scheduler.wait("z"), EditQueueFull);
  }
  for (std::thread& t : threads) t.join();
  EditScheduler::Turn again = scheduler.wait("z");  // room again
}

// Seeded: many clients, random frame counts; never two turns at once, every frame served.
TEST(EditScheduler, OneTurnAtATimeUnderContention) {
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    std::mt19937_64 rng(seed);
    EditScheduler scheduler(64);
    std::atomic<int> inside{0};
    std::atomic<int> overlaps{0}, served{0};
    std::vector<std::thread> threads;
    int frames = 0;
    for (int client = 0; client < 8; ++client) {
      const int n = std::uniform_int_distribution<int>(1, 6)(rng);
      frames += n;
      for (int k = 0; k < n; ++k)
        threads.emplace_back([&, client] {
          EditScheduler::Turn turn = scheduler.wait("c" + std::to_string(client));
          if (++inside != 1) ++overlaps;
          std::this_thread::sleep_for(std::chrono::microseconds(200));
          --inside;
          ++served;
        });
    }
    for (std::thread& t : threads) t.join();
    EXPECT_EQ(overlaps.load(), 0) << "seed " << seed;
    EXPECT_EQ(served.load(), frames) << "seed " << seed;
  }
}

}  // namespace
}  // namespace penumbra::server
