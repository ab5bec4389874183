// How fine a light's shadow overlap cube is (OverlapCubeSettings::grid = 0): G from the count
// of what casts, where a mesh that casts whole on its own faces counts as at most
// kMeshFacesCounted faces. Its faces never pair with each other in the cube (their
// self-shadowing is cast whole, at one rank per face) and cast on other receivers as one
// occluder, so tiles finer than the scene's other casters need only multiply tile entries: a
// small face of a model covers about a light's footprint of tiles, and a 70,000-triangle torus
// knot at G = 256 listed ~10^8 entries (2.7 GB, a minute) before its first cast. Any G finds
// every shadow relation (overlap_cube.h); G decides only how many extra pairs are listed.
#pragma once

#include <cstddef>

#include "core/scene/scene.h"

namespace penumbra {

inline constexpr size_t kMeshFacesCounted = 1024;

// OverlapCube::gridForFaceCount of the scene's faces, each mesh that casts whole on itself
// from light `light` (castsWholeOnItself, when `wholeObjects`) counted as
// min(its faces, kMeshFacesCounted).
int overlapGridFor(const Scene& scene, size_t light, bool wholeObjects);

}  // namespace penumbra
