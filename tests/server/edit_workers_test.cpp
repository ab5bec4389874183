// EditWorkers: work runs on a worker below the caller's CPU priority, the caller waits for it
// and gets its exception, and no more than `threads` jobs run at once however many callers.
#include "server/edit_workers.h"

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
  EditWorkers workers(2, 5);
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
  EditWorkers workers(1, 0);
  int niceThere = -100;
  workers.run([&] { niceThere = ownNiceness(); });
  EXPECT_EQ(niceThere, mine);
}

TEST(EditWorkers, TheCallerGetsTheWorksException) {
  EditWorkers workers(1, 3);
  EXPECT_THROW(workers.run([] { throw std::runtime_error("refused"); }), std::runtime_error);
  int after = 0;
  workers.run([&] { after = 1; });  // the worker survived it
  EXPECT_EQ(after, 1);
}

TEST(EditWorkers, ManyCallersAllRunAndAtMostThreadsAtOnce) {
  constexpr int kThreads = 2, kCallers = 12, kRuns = 40;
  EditWorkers workers(kThreads, 1);
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

// Heavy work (a frame relighting a whole scene) never takes the last worker: while heavy jobs of
// other scenes fill every slot they may, a light job still starts at once.
TEST(EditWorkers, HeavyWorkLeavesAWorkerForLightWork) {
  for (const int threads : {2, 3}) {
    EditWorkers workers(threads, 0);
    std::atomic<int> heavyRunning{0}, heavyMost{0};
    std::atomic<bool> release{false};
    std::vector<std::thread> heavy;
    for (int i = 0; i < 4; ++i)
      heavy.emplace_back([&] {
        workers.run(
            [&] {
              const int now = ++heavyRunning;
              int seen = heavyMost.load();
              while (now > seen && !heavyMost.compare_exchange_weak(seen, now)) {
              }
              while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
              --heavyRunning;
            },
            true);
      });
    for (int i = 0; i < 2000 && heavyRunning < threads - 1; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    // Every slot heavy work may use is held, more heavy work waits: a light job runs now.
    const auto start = std::chrono::steady_clock::now();
    bool ran = false;
    workers.run([&] { ran = true; });
    EXPECT_TRUE(ran);
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
    release = true;
    for (std::thread& t : heavy) t.join();
    EXPECT_EQ(heavyMost.load(), threads - 1) << threads << " workers";
  }
  EXPECT_EQ(EditWorkers(1, 0).threads(), 2u);  // one worker is never all there is
}

}  // namespace
}  // namespace penumbra::server
