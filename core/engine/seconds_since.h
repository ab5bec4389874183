// Wall seconds since a steady-clock point: the engine's step timings (BuildStats, FrameResult).
#pragma once

#include <chrono>

namespace penumbra {

inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace penumbra
