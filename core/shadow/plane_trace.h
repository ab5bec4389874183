// The trace of a 3D plane on a receiver's plane, as a signed-distance function in
// the receiver's 2D frame, with closed half-plane clipping and chords. Values; thread-safe.
#pragma once

#include <optional>

#include "core/geom/convex2d.h"
#include "core/geom/plane.h"
#include "core/geom/plane_frame.h"
#include "core/geom/tolerance.h"

namespace penumbra {

// Where a 3D plane meets the receiver's plane. A plane (nearly) parallel to the
// receiver's has no line there: the whole receiver plane is in front of it, behind
// it, or in it (Coincident: it constrains nothing on the receiver).
struct PlaneTrace {
  enum class Kind { Line, Front, Back, Coincident };
  Kind kind = Kind::Coincident;
  Vec2 normal{0.0};  // unit, in the frame; points to the 3D plane's front side
  double offset = 0;  // value(u) = normal·u + offset: 2D signed distance from the line

  // Parallel means |tilt| · sceneSize ≤ length tolerance: over the scene the
  // plane's distance from the receiver's plane varies by less than that.
  static PlaneTrace of(const Plane& plane, const PlaneFrame& frame, const Tolerance& tol);

  double value(const Vec2& u) const { return glm::dot(normal, u) + offset; }
};

// The part of a convex polygon on the trace's front side, closed: vertices within
// eps of the line count as on it and are kept unmoved; the polygon is returned
// unchanged if no vertex lies more than eps behind, empty if none lies more than
// eps in front. Front and Coincident keep everything; Back keeps nothing.
Polygon2 clipFrontOf(const Polygon2& polygon, const PlaneTrace& trace, double eps);

// The chord of a convex polygon along a Line trace (the segment of the line inside
// the closed polygon), or nullopt if it is shorter than minLength.
struct Chord {
  Vec2 a{0.0}, b{0.0};
};
std::optional<Chord> chordAlong(const Polygon2& polygon, const PlaneTrace& trace, double eps,
                                double minLength);

}  // namespace penumbra
