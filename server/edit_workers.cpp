#include "server/edit_workers.h"

#include <algorithm>

namespace penumbra::server {

namespace {

int oneOrPerCore(int threads) {
  return threads > 0 ? threads : std::max(1, int(std::thread::hardware_concurrency()));
}

}  // namespace

EditWorkers::EditWorkers(int threads, int niceness, int heavyNiceness)
    : light_(oneOrPerCore(threads), std::clamp(niceness, 0, 19), false),
      heavy_(1, std::clamp(light_.niceness() + std::max(0, heavyNiceness), 0, 19), true) {}

void EditWorkers::run(const std::function<void()>& work, bool heavy) {
  (heavy ? heavy_ : light_).run(work);
}

}  // namespace penumbra::server
