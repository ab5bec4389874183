// A convex face rebuilt from the triangles that tile it (Penumbra's own GLB export writes each
// scene face as its lit-mesh triangles, with the face named per vertex: penumbra_extras.h).
// Free function; thread-safe.
#pragma once

#include <optional>
#include <vector>

#include "core/geom/vec.h"
#include "interchange/polygon_repair.h"

namespace penumbra::interchange {

// The convex hull of the triangles' corners in their plane, counter-clockwise about the
// triangles' summed normal (the face's front), as indices into `positions`. Corners within
// `eps` of the line through their neighbours are left out: the points the lit mesh adds on a
// face's edges, which float32 storage moves off the edge by an ulp or so. Empty when the
// triangles have no area.
IndexPolygon convexOutline(const std::vector<Vec3>& positions,
                           const std::vector<IndexPolygon>& triangles, double eps);

// The faces a primitive's triangles tile, one per face number (`faceOf`: each vertex's face,
// the _FACE attribute), in face order, each its convexOutline() with eps = 4 float ulps of the
// largest coordinate. nullopt when a triangle's corners name different faces (not a Penumbra
// export: its triangles are joined as any file's).
std::optional<std::vector<IndexPolygon>> facesFromTriangles(
    const std::vector<Vec3>& positions, const std::vector<IndexPolygon>& triangles,
    const std::vector<double>& faceOf);

}  // namespace penumbra::interchange
