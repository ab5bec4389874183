#include "server/memory_trim.h"

#include <dlfcn.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace penumbra::server {

namespace {

// jemalloc's control entry point when it is the process's allocator (the programs link it,
// CMake PENUMBRA_JEMALLOC; tests and sanitizer builds run on glibc's malloc), else null.
using Mallctl = int (*)(const char*, void*, size_t*, void*, size_t);
Mallctl jemallocControl() {
  static const Mallctl control = reinterpret_cast<Mallctl>(dlsym(RTLD_DEFAULT, "mallctl"));
  return control;
}

// Gives the pages of freed memory back to the system, whichever allocator holds them.
void releaseFreedPages() {
  if (const Mallctl mallctl = jemallocControl()) {
    mallctl("arena.4096.purge", nullptr, nullptr, nullptr, 0);  // 4096 = MALLCTL_ARENAS_ALL
    return;
  }
#if defined(__GLIBC__)
  malloc_trim(0);  // frees whole free pages inside every arena, not only the top
#endif
}

}  // namespace

bool jemallocIsTheAllocator() { return jemallocControl() != nullptr; }

void limitMallocArenas(int arenas) {
#if defined(__GLIBC__)
  if (!jemallocIsTheAllocator()) mallopt(M_ARENA_MAX, arenas);
#else
  (void)arenas;
#endif
}

MemoryTrimmer::MemoryTrimmer(std::chrono::milliseconds interval)
    : interval_(interval), thread_([this] { run(); }) {}

MemoryTrimmer::~MemoryTrimmer() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void MemoryTrimmer::run() {
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, interval_, [this] { return stopping_; })) {
    if (!active_.exchange(false, std::memory_order_relaxed)) continue;
    lock.unlock();
    releaseFreedPages();
    ++trims_;
    lock.lock();
  }
}

}  // namespace penumbra::server
