// A part's irradiance as the binary mesh sends it (docs/API.md "Binary"): one value per vertex
// and a tint when every vertex's colour is one colour scaled, else r, g, b. Free functions; thread-safe.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/geom/vec.h"

namespace penumbra::server::mesh_binary {

struct TintedIrradiance {
  // 1: vertex i's irradiance is (values[i]·tint[0], values[i]·tint[1], values[i]·tint[2]),
  // each product taken in f32; 3: values holds r, g, b per vertex.
  uint32_t channels = 3;
  std::array<float, 3> tint{1.0f, 1.0f, 1.0f};  // (1, 1, 1) when channels = 3
  std::vector<float> values;
};

// One channel when the vertices are proportional to one colour within f32 rounding: the tint is
// the brightest vertex's colour over its largest channel (white gives exactly (1, 1, 1)), a
// vertex's value its irradiance in that channel, and every decoded channel lies within 2 f32
// units in the last place of the channel's f32 value (as under one light of any colour); else
// three. Zero vertices fit any tint; an empty or all-zero part is one channel, tint (1, 1, 1).
TintedIrradiance tintIrradiance(const std::vector<Vec3>& irradiance);

}  // namespace penumbra::server::mesh_binary
