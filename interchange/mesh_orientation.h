// One object's faces as a surface: connected components across shared edges, which of them
// are closed, and the faces flipped so that each component is wound one way (closed ones
// outward). Free functions on plain values; thread-safe.
#pragma once

#include <vector>

#include "core/geom/vec.h"
#include "interchange/polygon_repair.h"

namespace penumbra::interchange {

// Edges are undirected pairs of (welded) vertex indices. Two faces are neighbours when they
// share an edge that no third face uses; a component is a set of faces joined by neighbours.
// A component is closed when every edge of its faces is shared by exactly two of them running
// opposite ways (so it bounds a volume); an edge of three or more faces is non-manifold.
struct SurfaceFacts {
  size_t components = 0;
  size_t closedComponents = 0;
  size_t nonManifoldEdges = 0;  // shared by 3+ faces: left as they are
  size_t boundaryEdges = 0;     // of one face only (open surfaces)
  size_t nonOrientableComponents =
      0;  // no choice of flips makes every shared edge run opposite ways
  // Set by orientFaces only:
  size_t facesFlipped = 0;                   // all flips, whatever the reason
  size_t closedComponentsTurnedOutward = 0;  // wound inside out as a whole (negative volume)
  size_t closedComponentsAroundLights = 0;   // enclose a light: wound to face inward (a room)
};

// Facts only: `faces` as they are.
SurfaceFacts surfaceFacts(const std::vector<IndexPolygon>& faces);

// Reverses faces so that across every edge shared by exactly two faces of a component the two
// run opposite ways, flipping the fewer faces of each component; then a closed component with
// negative signed volume is reversed whole (outward, positive volume), unless it encloses one
// of `insidePoints` (the scene's lights: a closed room around them faces inward). Components
// whose volume is zero to rounding (a two-sided sheet) are not turned. Returns the facts after.
SurfaceFacts orientFaces(const std::vector<Vec3>& positions, std::vector<IndexPolygon>& faces,
                         const std::vector<Vec3>& insidePoints);

// The winding number of the closed surface `faces` about `point` (1 inside an outward surface,
// −1 inside an inward one, 0 outside), by summing the solid angles of fan triangles.
double windingNumber(const std::vector<Vec3>& positions, const std::vector<IndexPolygon>& faces,
                     const Vec3& point);

}  // namespace penumbra::interchange
