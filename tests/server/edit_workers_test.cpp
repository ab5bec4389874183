// EditWorkers: work runs on a worker below the caller's CPU priority, the caller waits for it
// and gets its exception, no more than `threads` jobs run at once however many callers, and heavy
// work keeps to its own lower-priority lane.
#include "server/edit_workers.h"

#include "core/util/parallel.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

namespace penumbra::server {
namespace {

int ownNiceness() {
  errno = 0;
  const int nice = getpriority(PRIO_PROCESS, id_t(gettid()));
  EXPECT_EQ(errno, 0);
  return nice;
}

TEST(EditWorkers, WorkRunsOnAnotherThreadBelowTheCallersPriority) {
  const int mine = ownNiceness();
  EditWorkers workers(2, 5, 0);
  std::thread::id ranOn;
  int niceThere = -100;
  workers.run([&] {
    ranOn = std::this_thread::get_id();
    niceThere = ownNiceness();
  });
  EXPECT_NE(ranOn, std::this_thread::get_id());
  EXPECT_EQ(niceThere, std::min(19, mine + 5));
  EXPECT_EQ(ownNiceness(), mine);  // the caller's own priority is untouched
}

TEST(EditWorkers, NicenessZeroKeepsThePriority) {
  const int mine = ownNiceness();
  EditWorkers workers(1, 0, 0);
  int niceThere = -100;
  workers.run([&] { niceThere = ownNiceness(); });
  EXPECT_EQ(niceThere, mine);
}

TEST(EditWorkers, TheCallerGetsTheWorksException) {
  EditWorkers workers(1, 3, 0);
  EXPECT_THROW(workers.run([] { throw std::runtime_error("refused"); }), std::runtime_error);
  int after = 0;
  workers.run([&] { after = 1; });  // the worker survived it
  EXPECT_EQ(after, 1);
}

TEST(EditWorkers, ManyCallersAllRunAndAtMostThreadsAtOnce) {
  constexpr int kThreads = 2, kCallers = 12, kRuns = 40;
  EditWorkers workers(kThreads, 1, 0);
  std::atomic<int> running{0}, most{0}, done{0};
  std::vector<std::thread> callers;
  for (int c = 0; c < kCallers; ++c)
    callers.emplace_back([&] {
      for (int r = 0; r < kRuns; ++r)
        workers.run([&] {
          const int now = ++running;
          int seen = most.load();
          while (now > seen && !most.compare_exchange_weak(seen, now)) {
          }
          std::this_thread::sleep_for(std::chrono::microseconds(200));
          --running;
          ++done;
        });
    });
  for (std::thread& t : callers) t.join();
  EXPECT_EQ(done.load(), kCallers * kRuns);
  EXPECT_LE(most.load(), kThreads);
  EXPECT_EQ(most.load(), kThreads);  // with 12 callers waiting, both workers were busy at once
}

// Heavy work (a frame relighting a whole scene) runs on its own lane: one job at a time, on one
// thread `heavyNiceness` steps below the light workers, its engine loops on that thread alone;
// while heavy jobs hold and fill the lane, light jobs start at once on their own workers.
TEST(EditWorkers, HeavyWorkRunsOneAtATimeBelowTheLightWorkersAndNeverHoldsThemUp) {
  const int mine = ownNiceness();
  for (const int threads : {1, 2}) {
    EditWorkers workers(threads, 2, 5);
    EXPECT_EQ(workers.threads(), size_t(threads) + 1);
    EXPECT_EQ(workers.heavyNiceness(), std::min(19, 2 + 5));
    std::atomic<int> heavyRunning{0}, heavyMost{0}, heavyNice{-100};
    std::atomic<bool> release{false}, loopsHere{true};
    std::vector<std::thread> heavy;
    for (int i = 0; i < 3; ++i)
      heavy.emplace_back([&] {
        workers.run(
            [&] {
              const int now = ++heavyRunning;
              int seen = heavyMost.load();
              while (now > seen && !heavyMost.compare_exchange_weak(seen, now)) {
              }
              heavyNice = ownNiceness();
              // An engine loop of many items stays on this thread.
              const auto self = std::this_thread::get_id();
              Parallel(2).forEach(64, [&](size_t) {
                if (std::this_thread::get_id() != self) loopsHere = false;
              });
              while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
              --heavyRunning;
            },
            true);
      });
    for (int i = 0; i < 5000 && (heavyRunning < 1 || workers.heavyQueued() < 2); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ASSERT_EQ(workers.heavyQueued(), 2u);  // one heavy job runs, the others wait for the lane
    // The lane is held and has a queue: light jobs still run now, on every light worker.
    for (int i = 0; i < 2 * threads; ++i) {
      const auto start = std::chrono::steady_clock::now();
      int lightNice = -100;
      workers.run([&] { lightNice = ownNiceness(); });
      EXPECT_EQ(lightNice, std::min(19, mine + 2));
      EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
    }
    release = true;
    for (std::thread& t : heavy) t.join();
    EXPECT_EQ(heavyMost.load(), 1) << threads << " light workers";
    EXPECT_EQ(heavyNice.load(), std::min(19, mine + 7));
    EXPECT_TRUE(loopsHere.load());
  }
}

}  // namespace
}  // namespace penumbra::server
