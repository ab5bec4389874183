// A "scanned" object: a closed sphere-topology mesh with seeded radial noise, like a
// range scan of a lumpy stone. Pure; thread-safe.
#pragma once

#include <cstdint>

#include "scenegen/tri_mesh.h"

namespace penumbra {

struct ScanOptions {
  int triangles = 70000;  // about; 20 · f² for the subdivision frequency f
  uint64_t seed = 1;
};

// The icosahedron with each face cut into f² triangles (f = round(√(triangles / 20)) ≥ 1),
// its lattice points on the unit sphere, each moved along its direction to radius
// r(u) = 1 + Σ bumps (12 seeded Gaussian lumps and dents, each up to ±0.12)
// + a seeded per-vertex jitter (±0.4 % of the radius, the scanner's noise). A radial
// graph over the sphere (r > 0) is embedded, so the mesh is closed, has sphere topology
// and keeps the icosahedron's outward orientation. Points on a shared edge are computed
// once from that edge's end points. Throws std::invalid_argument for fewer than 20 triangles.
TriMesh scanMesh(const ScanOptions& options);

}  // namespace penumbra
