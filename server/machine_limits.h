// Limits sized from the machine the server runs on. The engine's per-scene byte budget defaults
// to 16 GiB whatever the machine (on a 24 GB machine one scene could take two thirds of it): the
// server gives each scene at most a quarter of the physical memory.
#pragma once

#include <cstdint>

#include "core/engine/resource_budget.h"

namespace penumbra::server {

uint64_t physicalMemoryBytes();  // 0 when the system does not say

// `limits` with bytes at most a quarter of `physicalBytes` (unchanged when that is 0).
ResourceLimits limitsForMachine(ResourceLimits limits, uint64_t physicalBytes);

}  // namespace penumbra::server
