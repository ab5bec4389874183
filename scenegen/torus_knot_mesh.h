// A (p, q) torus knot as a closed tube of triangles. Pure; thread-safe.
#pragma once

#include "scenegen/tri_mesh.h"

namespace penumbra {

struct TorusKnotOptions {
  int p = 2, q = 3;          // turns around the torus's axis and through its hole (coprime)
  double tubeRadius = 0.35;  // in units of the torus's tube radius (the torus is R = 2, r = 1)
  int triangles = 6000;      // about; 2 · segments · sides
};

// The centre line c(t) = ((2 + cos qt) cos pt, −sin qt, (2 + cos qt) sin pt), t ∈ [0, 2π),
// with a ring of `sides` vertices round it at each of `segments` steps (segments / sides ≈
// the line's length over the tube's circumference, so cells are about square). Each ring
// lies in the plane normal to c′ through c(t), its frame the offset from the torus's core
// circle to c(t) made normal to c′: periodic, so the last ring joins the first (closed).
// Counter-clockwise seen from outside. Throws std::invalid_argument for p, q < 1, a tube
// radius outside (0, 0.5] or fewer than 24 triangles.
TriMesh torusKnotMesh(const TorusKnotOptions& options);

}  // namespace penumbra
