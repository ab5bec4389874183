// An open hemispherical bowl: one sheet of one-sided triangles with an open rim. Pure;
// thread-safe.
#pragma once

#include "scenegen/tri_mesh.h"

namespace penumbra {

// The lower half of the unit sphere about the origin (rim: the unit circle at y = 0,
// bottom pole at (0, −1, 0)) in `stacks` latitude bands of `slices` vertices: a fan round
// the pole, two triangles per cell above, slices · (2 · stacks − 1) triangles about
// `triangles` (slices ≈ 2 · stacks). Its faces face the sphere's centre: the inside of
// the bowl, which looks up at a ceiling light; the outside is their back. One open
// boundary loop, the rim (slices edges); every other edge is shared by two triangles in
// opposite directions. Throws std::invalid_argument for fewer than 24 triangles.
TriMesh bowlMesh(int triangles);

}  // namespace penumbra
