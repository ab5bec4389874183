// Gives freed heap memory back to the system while the server runs: a thread that, after
// activity, purges jemalloc's arenas (the programs' allocator) or calls glibc's malloc_trim (tests,
// sanitizer builds): both keep freed pages otherwise. Thread-safe.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace penumbra::server {

// True when jemalloc serves malloc in this process (found at run time).
bool jemallocIsTheAllocator();

// Caps glibc's malloc arenas for a process serving many threads (each thread would
// otherwise get an arena, up to 8 per core, each keeping its own freed pages). Call once,
// before the server's threads start; a no-op under jemalloc and elsewhere than glibc.
void limitMallocArenas(int arenas);

class MemoryTrimmer {
 public:
  explicit MemoryTrimmer(std::chrono::milliseconds interval);
  ~MemoryTrimmer();  // stops and joins the thread
  MemoryTrimmer(const MemoryTrimmer&) = delete;
  MemoryTrimmer& operator=(const MemoryTrimmer&) = delete;

  // Something allocated and freed memory (a request was served): trim at the next tick.
  void noteActivity() { active_.store(true, std::memory_order_relaxed); }
  size_t trims() const { return trims_.load(); }

 private:
  void run();

  const std::chrono::milliseconds interval_;
  std::atomic<bool> active_{false};
  std::atomic<size_t> trims_{0};
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace penumbra::server
