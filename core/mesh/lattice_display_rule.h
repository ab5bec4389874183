// Which receivers are displayed from their lattice squares (lattice_mesh_memo.h) rather than
// their DM-tree cells (receiver_mesh_memo.h): those whose DM is far denser than a display
// needs, and whose value a square's interpolation can follow (docs/DESIGN.md "Lattice
// display"). A pure function of the tree and the scene, so a fresh memo and a kept one choose
// alike. Thread-safe.
#pragma once

#include "core/mesh/cell_lighting.h"
#include "core/mesh/receiver_mesh_memo.h"

namespace penumbra {

// True when all of these hold:
// - the grid has a lattice, a refinement tolerance and grid.latticeAbove > 0;
// - the face is flat-shaded (no corner normals: a cell's piece interpolates those);
// - nothing in any cell's list touches or crosses the face's plane (a contact line is a value
//   jump, D0, which only a cell edge follows);
// - some lattice square holds more than grid.latticeAbove live DM vertices. Under a tessellated
//   model's shadow a square holds thousands (silhouette lines crossing in the penumbra); in the
//   dense room of 150 boxes at most 355 (BENCHMARKS.md "Lattice display").
bool displaysFromLattice(const Scene& scene, const MeshSource& source, const MeshGrid& grid);

}  // namespace penumbra
