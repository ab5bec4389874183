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
// - the grid has a lattice, a lattice tolerance and grid.latticeAbove > 0 (the squares are
//   refined even where the cells are not: MeshGrid::latticeTolerance);
// - the face is flat-shaded (no corner normals: a cell's piece interpolates those);
// - nothing in any cell's list touches or crosses the face's plane (a contact line is a value
//   jump, D0, which only a cell edge follows);
// - some lattice square holds more than grid.latticeAbove live DM vertices. Under a tessellated
//   model's shadow a square holds thousands (silhouette lines crossing in the penumbra); in the
//   dense room of 150 boxes at most 355 (BENCHMARKS.md "Lattice display");
// - the cells outnumber the tree's distinct occluder lists more than kCellsPerDistinctList
//   times. Under a model one list (the whole model) holds all the shadowed cells: its lines
//   part cells with the same occluders, where the value is smooth and a square's few test
//   points follow it. Where each few cells have a list of their own (box clutter: the dense
//   room of 1,500 boxes, 42 cells a list on its floor), each list's region is a feature a
//   square would have to find: there squares capped at their point limit were up to 12 % off.
constexpr size_t kCellsPerDistinctList = 1000;
bool displaysFromLattice(const Scene& scene, const MeshSource& source, const MeshGrid& grid);

}  // namespace penumbra
