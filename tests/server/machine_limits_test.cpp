// The per-scene byte budget follows the machine: a quarter of its memory, never more than the
// engine's default; a machine that does not say keeps the default.
#include "server/machine_limits.h"

#include <gtest/gtest.h>

namespace penumbra::server {
namespace {

TEST(MachineLimits, ASceneGetsAtMostAQuarterOfTheMemory) {
  const ResourceLimits defaults;
  const uint64_t gib = uint64_t(1) << 30;
  EXPECT_EQ(limitsForMachine(defaults, 24 * gib).bytes, 6 * gib);
  EXPECT_EQ(limitsForMachine(defaults, 128 * gib).bytes, defaults.bytes);  // the default caps it
  EXPECT_EQ(limitsForMachine(defaults, 0).bytes, defaults.bytes);
  EXPECT_EQ(limitsForMachine(defaults, 24 * gib).faces, defaults.faces);  // the rest unchanged
  EXPECT_GT(physicalMemoryBytes(), gib);                                  // this machine says
}

}  // namespace
}  // namespace penumbra::server
