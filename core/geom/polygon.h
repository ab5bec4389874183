// Planar polygons in 3D as vertex lists (counter-clockwise seen from the front).
// Free functions only; thread-safe.
#pragma once

#include <optional>
#include <vector>

#include "core/geom/plane.h"
#include "core/geom/vec.h"

namespace penumbra {

using Polygon3 = std::vector<Vec3>;

// Newell's vector: twice the vector area; its direction is the front normal.
Vec3 newellVector(const Polygon3& polygon);
double area(const Polygon3& polygon);
Vec3 centroid(const Polygon3& polygon);  // vertex average
// Largest distance between two vertices.
double extent(const Polygon3& polygon);

// The polygon's plane (normal from Newell), or nullopt if its area is ~zero
// relative to its extent.
std::optional<Plane> planeOf(const Polygon3& polygon);

// Largest vertex distance from the polygon's plane, relative to its extent.
double planarityError(const Polygon3& polygon);

// Twice the area over the extent: the height of a triangle over its longest side,
// twice the thickness of a thin rectangle. 0 for fewer than 3 vertices.
double width(const Polygon3& polygon);

// Every vertex moved along the plane's normal onto the plane.
Polygon3 projectedOnto(const Polygon3& polygon, const Plane& plane);

// Convex (no reflex corner, no self-overlap) and counter-clockwise about its own
// Newell normal. Collinear corners are allowed.
bool isConvex(const Polygon3& polygon);

// Removes vertices that coincide with their predecessor (within eps).
Polygon3 withoutDuplicateVertices(const Polygon3& polygon, double eps);

}  // namespace penumbra
