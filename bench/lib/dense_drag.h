// The "move one box" edit script of the dense rooms (makeDenseScene): one floating box
// dragged horizontally in small steps through free space. Pure function of (scene,
// frames, seed); thread-safe.
#pragma once

#include <cstdint>

#include "bench/lib/edit_scripts.h"

namespace penumbra {

inline constexpr double kDenseDragStep = 0.02;    // metres per frame
inline constexpr double kDenseDragTurnDeg = 0.5;  // and a small turn about its vertical axis

// Script "drag": the box (object "box_<i>") whose centre is closest to the middle of the
// room under the light, (0, kDenseHeight / 2, 0) — its shadow falls on the floor under the
// light and on the boxes below, the costly case — slid `frames` steps of kDenseDragStep
// along one of 16 horizontal directions (the seed picks where the search starts) whose
// swept bounding sphere stays kDenseGap clear of every other box's sphere, the walls,
// the floor and the light's plane, so boxes never touch. If no direction is clear for
// the whole length, the next-closest boxes (32 in all), then the longest clear path
// (halving the length). Throws std::invalid_argument if the scene has no box.
EditScript denseDragScript(const Scene& scene, int frames, uint64_t seed);

}  // namespace penumbra
