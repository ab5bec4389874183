// EditScheduler: one batch at a time, frames that queued meanwhile taken together (one per
// client, in turn order), a full queue refuses. Threads stand in for request workers; the
// batches are checked exactly.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
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

// Records each batch as the clients of its frames.
struct BatchLog {
  std::mutex mutex;
  std::vector<std::vector<std::string>> batches;
  EditScheduler::ApplyBatch recorder() {
    return [this](const std::vector<EditScheduler::Ticket*>& batch) {
      std::vector<std::string> clients;
      for (const EditScheduler::Ticket* t : batch) clients.push_back(t->client);
      std::lock_guard lock(mutex);
      batches.push_back(clients);
    };
  }
};

// "first" applies (held open) while A sends three frames, then B one, then C two.
std::vector<std::vector<std::string>> batchesAfterAHeldTurn(size_t maxBatch) {
  EditScheduler scheduler(16, maxBatch);
  BatchLog log;
  std::promise<void> release, applying;
  std::shared_future<void> released = release.get_future().share();
  std::thread first([&] {
    EditScheduler::Ticket ticket{"first"};
    scheduler.submit(ticket, [&](const std::vector<EditScheduler::Ticket*>&) {
      applying.set_value();
      released.wait();
    });
  });
  // "first" is applying: its batch has started (polling for an empty queue raced with the
  // thread's start on a loaded machine, and the next frames then applied at once).
  applying.get_future().wait();
  std::vector<std::thread> threads;
  std::vector<EditScheduler::Ticket> tickets(6);
  size_t queued = 0;
  for (const char* client : {"A", "A", "A", "B", "C", "C"}) {
    EditScheduler::Ticket& ticket = tickets[queued];
    ticket.client = client;
    threads.emplace_back([&] { scheduler.submit(ticket, log.recorder()); });
    waitUntilQueued(scheduler, ++queued);
  }
  release.set_value();
  first.join();
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(scheduler.queued(), 0u);
  for (const EditScheduler::Ticket& t : tickets) EXPECT_TRUE(t.done);
  return log.batches;
}

TEST(EditScheduler, FramesThatQueuedTogetherApplyTogetherOnePerClient) {
  using Batches = std::vector<std::vector<std::string>>;
  EXPECT_EQ(batchesAfterAHeldTurn(16), (Batches{{"A", "B", "C"}, {"A", "C"}, {"A"}}));
  EXPECT_EQ(batchesAfterAHeldTurn(2), (Batches{{"A", "B"}, {"C", "A"}, {"C", "A"}}));
  EXPECT_EQ(batchesAfterAHeldTurn(1), (Batches{{"A"}, {"B"}, {"C"}, {"A"}, {"C"}, {"A"}}));
}

TEST(EditScheduler, FullQueueRefusesAndRecovers) {
  EditScheduler scheduler(2, 16);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::thread holder([&] {
    EditScheduler::Ticket ticket{"x"};
    scheduler.submit(ticket, [&](const std::vector<EditScheduler::Ticket*>&) { released.wait(); });
  });
  waitUntilQueued(scheduler, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  std::vector<EditScheduler::Ticket> waiting(2, EditScheduler::Ticket{"y"});
  std::vector<std::thread> threads;
  const auto nothing = [](const std::vector<EditScheduler::Ticket*>&) {};
  for (size_t i = 0; i < 2; ++i) {
    threads.emplace_back([&, i] { scheduler.submit(waiting[i], nothing); });
    waitUntilQueued(scheduler, i + 1);
  }
  EditScheduler::Ticket refused{"z"};
  EXPECT_THROW(scheduler.submit(refused, nothing), EditQueueFull);
  EXPECT_FALSE(refused.done);
  release.set_value();
  holder.join();
  for (std::thread& t : threads) t.join();
  EditScheduler::Ticket again{"z"};
  scheduler.submit(again, nothing);  // room again
  EXPECT_TRUE(again.done);
}

// Seeded: many clients, random frame counts; never two batches at once, never two frames of
// one client in a batch, every frame applied exactly once and done when submit returns.
TEST(EditScheduler, OneBatchAtATimeUnderContention) {
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    std::mt19937_64 rng(seed);
    EditScheduler scheduler(64, 4);
    std::atomic<int> inside{0}, overlaps{0}, applied{0}, sameClient{0}, notDone{0};
    const auto apply = [&](const std::vector<EditScheduler::Ticket*>& batch) {
      if (++inside != 1) ++overlaps;
      std::vector<std::string> clients;
      for (const EditScheduler::Ticket* t : batch) {
        if (std::find(clients.begin(), clients.end(), t->client) != clients.end()) ++sameClient;
        clients.push_back(t->client);
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      applied += int(batch.size());
      --inside;
    };
    std::vector<std::thread> threads;
    int frames = 0;
    for (int client = 0; client < 8; ++client) {
      const int n = std::uniform_int_distribution<int>(1, 6)(rng);
      frames += n;
      for (int k = 0; k < n; ++k)
        threads.emplace_back([&, client] {
          EditScheduler::Ticket ticket{"c" + std::to_string(client)};
          scheduler.submit(ticket, apply);
          if (!ticket.done) ++notDone;
        });
    }
    for (std::thread& t : threads) t.join();
    EXPECT_EQ(overlaps.load(), 0) << "seed " << seed;
    EXPECT_EQ(sameClient.load(), 0) << "seed " << seed;
    EXPECT_EQ(notDone.load(), 0) << "seed " << seed;
    EXPECT_EQ(applied.load(), frames) << "seed " << seed;
  }
}

}  // namespace
}  // namespace penumbra::server
