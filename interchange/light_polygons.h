// The emissive faces of one imported group → its light polygons: each face turned
// to face the lit scene, then neighbours that form one flat convex polygon joined
// (a quad light given as two triangles is one light). Free function; thread-safe.
#pragma once

#include <optional>
#include <vector>

#include "core/geom/polygon.h"
#include "interchange/import_report.h"
#include "interchange/polygon_repair.h"

namespace penumbra::interchange {

// `faces` index `positions` (welded: shared corners have one index), each convex and
// planar. `litCentre`: the middle of the non-emissive geometry, if any; a face whose
// front does not see it is reversed. Counts `lights_turned_to_face_the_scene` (per
// resulting light) and `coplanar_light_triangles_joined` (per join) in `report`.
std::vector<Polygon3> lightPolygons(const std::vector<Vec3>& positions, std::vector<IndexPolygon> faces,
                                    const std::optional<Vec3>& litCentre, ImportReport& report);

}  // namespace penumbra::interchange
