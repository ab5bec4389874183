// Closed convex objects: whether an object's faces bound a convex solid, so that no
// face of it can shadow another (DESIGN.md "Closed objects"). Pure functions; thread-safe.
#pragma once

#include <cstddef>
#include <vector>

#include "core/geom/tolerance.h"
#include "core/scene/scene.h"

namespace penumbra {

// Watertight and consistently oriented: after welding vertices at equal object-space
// positions, every edge of the object's faces is traversed exactly twice, once in each
// direction. Edges of zero length (a vertex repeated) are ignored.
bool isClosedOriented(const Object& object);

// Every vertex of `faces` lies on or behind every one of their planes, within `eps`
// (the faces of one object, in world space, CCW from their front).
bool isConvexWithin(const std::vector<Face>& faces, double eps);

// The convexity test costs faces × distinct vertices; an object past this budget
// (~10,000 faces) is not tested and counts as not convex: it casts on itself.
inline constexpr size_t kConvexCheckBudget = 50'000'000;

// Closed, consistently oriented and convex within tolerance.length(): then for p on a
// face f, every other face lies in the closed half-space behind f's plane while the
// light reaching p comes from in front of it, so the object never shadows itself.
// Closed and convex together also make the orientation outward (an inward-facing
// closed object has its vertices in front of its planes). `worldFaces` are the
// object's faces as Scene::facesOf makes them.
bool isClosedConvex(const Object& object, const std::vector<Face>& worldFaces,
                    const Tolerance& tolerance);

}  // namespace penumbra
