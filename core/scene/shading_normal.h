// Smooth shading: an object may give each face corner its own normal (Object::normals, the
// OBJ `vn` / glTF NORMAL of a tessellated model). Irradiance is then taken about the normal
// interpolated at the point (core/illum/backprojection.h): Lambert's formula for that normal
// over the visible light clipped to its front, so the value is exact for the shading normal
// and curved models stop looking faceted. Visibility (what blocks the light, the single-sided
// rule, the discontinuities) stays with the face's own plane. Free functions; thread-safe.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/geom/plane.h"
#include "core/geom/polygon.h"
#include "core/scene/transform.h"

namespace penumbra {

// What is wrong with an object's `normals` against its faces (one list per face, one finite,
// non-zero vector per corner), or nothing.
std::optional<std::string> normalsProblem(const std::vector<std::vector<Vec3>>& normals,
                                          const std::vector<std::vector<int>>& faces);

// Face `f`'s corner normals in world space (unit, in the order of its world polygon, which a
// mirroring transform reverses), or empty when the object has none or some corner's normal
// does not point strictly to the front of the face's world plane (the face is shaded flat).
std::vector<Vec3> worldCornerNormals(const std::vector<std::vector<Vec3>>& normals, size_t f,
                                     const Transform& transform, const Plane& plane);

// The shading normal at p on a convex planar polygon with unit corner normals `corners`
// (empty: `flat`): the corners' normals interpolated barycentrically in the fan triangle from
// corner 0 that holds p (the nearest one when p lies just outside), normalized. Interpolating
// normals in front of a plane stays in front of it.
Vec3 interpolatedNormal(const Polygon3& polygon, const std::vector<Vec3>& corners, const Vec3& flat,
                        const Vec3& p);

// Corner normals that smooth a mesh across its edges: at each corner, the mean of the normals
// of the faces meeting at that vertex index, weighted by their corner angles, keeping only faces
// within `creaseDeg` of the corner's own face (so a rim or a box edge stays sharp). Faces index
// `vertices`, counter-clockwise from the front; a degenerate face keeps its own normal.
std::vector<std::vector<Vec3>> smoothCornerNormals(const std::vector<Vec3>& vertices,
                                                   const std::vector<std::vector<int>>& faces,
                                                   double creaseDeg = 60);

}  // namespace penumbra
