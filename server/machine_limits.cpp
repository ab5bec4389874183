#include "server/machine_limits.h"

#include <unistd.h>

#include <algorithm>

namespace penumbra::server {

uint64_t physicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long pageSize = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || pageSize <= 0) return 0;
  return uint64_t(pages) * uint64_t(pageSize);
}

ResourceLimits limitsForMachine(ResourceLimits limits, uint64_t physicalBytes) {
  if (physicalBytes > 0) limits.bytes = size_t(std::min<uint64_t>(limits.bytes, physicalBytes / 4));
  return limits;
}

}  // namespace penumbra::server
