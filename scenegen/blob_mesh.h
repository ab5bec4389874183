// An isosurface blob: the closed surface of a few seeded metaballs, by marching
// tetrahedra. Pure; thread-safe.
#pragma once

#include <cstdint>

#include "scenegen/tri_mesh.h"

namespace penumbra {

struct BlobOptions {
  int triangles = 6000;  // about: the grid is sized for it
  uint64_t seed = 1;
  int balls = 5;  // metaballs, 1..16
};

// The set {x : Σᵢ exp(−|x − cᵢ|² / sᵢ²) ≥ ½} of `balls` Gaussian metaballs, seeded: centres
// a random walk of steps 0.7 s (so they merge into one body), radii s in [0.3, 0.5].
// Sampled on a cubic grid of cells of side h, each cut into the six Kuhn tetrahedra round its
// main diagonal (neighbouring cells cut their shared faces alike); on each tetrahedron
// the surface is one triangle or a quad (split along its shorter diagonal). A point is
// made once per grid edge (its parameter kept in [0.05, 0.95], so no triangle shrinks
// into a grid corner) and shared by every tetrahedron round that edge: the mesh is closed
// (watertight). Orientation follows from each tetrahedron's own orientation and which
// corners are inside: counter-clockwise seen from outside, with no numerical test.
// h is searched for `triangles` (the nearest count of seven sizes 4 % apart round the
// estimate, three from 20,000 on); each grid is shifted by a seeded part of a cell until no
// triangle is thinner than 1 % of a cell (the thickest of 8 tries otherwise).
// Throws std::invalid_argument for fewer than 100 triangles or balls outside 1..16.
TriMesh blobMesh(const BlobOptions& options);

}  // namespace penumbra
