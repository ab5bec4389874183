// The Utah teapot: Newell's 32 bicubic Bézier patches (rim, body, handle, spout, lid,
// bottom) tessellated into one welded triangle mesh. Pure; thread-safe.
//
// Not watertight, as the patch data is not: the mesh has exactly six open boundary loops —
//   the body's rim (the inner edge of the lip, radius 1.4, height 2.4 in patch units),
//   the lid's rim (radius 1.3, height 2.4: the lid sits in the opening, apart from the body),
//   the two ends of the handle (x < −1.4, on the body's surface, not joined to it),
//   the spout's base (x = 1.7, on the body, not joined) and its tip (x ≥ 2.8, open).
// Every other edge has its two triangles in opposite directions; the handle's lower end
// shares one control point with the body, (−2, 0, 0.9), so one vertex is shared there.
#pragma once

#include "scenegen/tri_mesh.h"

namespace penumbra {

// Steps per patch side along u (across the patch's rows) and v (along each row).
struct TeapotSteps {
  int u = 10, v = 10;
};

// 64·u·v − 8·v triangles: 2 per grid cell of the 32 patches, less the v cells at the
// pole of each of the 8 lid-top and bottom patches, whose one triangle collapses.
size_t teapotTriangleCount(const TeapotSteps& steps);

// Steps for about `triangles` (at least 2 × 2): the nearest u = v when its count is within
// 15 %, else the nearest with |u − v| ≤ 1: 1,000 → 4 × 4 (992), 6,000 → 10 × 10 (6,320).
TeapotSteps teapotStepsFor(int triangles);

// y up (patch z becomes y, patch y becomes −z: the spout towards +x), in patch units
// (3.15 high, the bottom's centre at the origin). Patch boundaries are evaluated from
// their four control points in one canonical order, so the grids of neighbouring patches
// meet at bit-equal points and weld; triangles that collapse at the poles are dropped.
// Counter-clockwise seen from outside. Throws std::invalid_argument for steps < 1.
TriMesh teapotMesh(const TeapotSteps& steps);

}  // namespace penumbra
