// The composition filter of seed 001 ("Final image composition", Fig. 8): a Gaussian over the
// (2r+1)² neighbours that lie on the same surface as the pixel (k_ij = 0 across an id edge),
// its weights renormalised to sum to 1 over those. Smooths the tiles' interpolation seams
// without carrying light across edges. Pure function; thread-safe.
#pragma once

#include <cstdint>
#include <vector>

#include "core/geom/vec.h"
#include "core/util/parallel.h"

namespace penumbra::gi {

// id[p] < 0: no surface (left 0). radius 0 returns the values unchanged (on surfaces).
std::vector<Vec3> idAwareGaussian(int width, int height, const std::vector<Vec3>& values,
                                  const std::vector<int32_t>& id, int radius, double sigma,
                                  const Parallel& parallel);

}  // namespace penumbra::gi
