// PenumbraVolume: the penumbra shadow volume PSV(P) of a convex face P lit by a
// convex light S, as half-spaces (paper §2.2). Plain value, set once; thread-safe.
#pragma once

#include <optional>
#include <vector>

#include "core/geom/plane.h"
#include "core/geom/polygon.h"
#include "core/geom/tolerance.h"

namespace penumbra {

// The points x behind P that some segment from a point of S through P reaches:
// X = { x : dist_P(x) ≤ 0 and conv({x} ∪ S') meets P }, with S' the part of S
// strictly in front of P's plane. X is convex; it is bounded by P's plane and by
// the separating supporting planes of S' and P (through an edge of one and a
// vertex of the other, S' and P on opposite sides).
//
// Conservative by construction: a candidate plane is kept only after checking,
// with its own computed normal, that all of S' lies on one closed side and all
// of P on the other (up to length() of rounding noise: supporting planes touch
// both), it is placed through P's outermost vertex, and (VolumeMargin::Conservative)
// every half-space is widened by Tolerance::onPlane(). Degenerate candidates are dropped, which
// only enlarges the volume.
struct PenumbraVolume {
  // Outward planes: x is inside iff signedDistance(x) ≤ 0 for every plane.
  // bounds[0] is P's own plane (widened); the rest are separating planes.
  std::vector<Plane> bounds;

  bool contains(const Vec3& x) const;
  // The part of a convex polygon inside the volume; empty if it has no positive
  // area (vertices within eps of a bound count as on it).
  Polygon3 clipInside(const Polygon3& polygon, double eps) const;
  // Every vertex of `polygon` at a positive distance outside one bound: every part of it is
  // then more than any eps (≥ 0, far above rounding) outside that bound, so clipInside is empty.
  // A quick reject with no allocation for tests asked of many pairs (the front-to-back order's).
  bool outsideABound(const Polygon3& polygon) const;
  // Throws std::logic_error unless there is at least P's plane and every normal
  // is finite and unit.
  void validate() const;
};

// How far the volume's half-spaces are pushed out: the overlap cube must never
// miss a shadow (Conservative: by Tolerance::onPlane()); the front-to-back order
// must not invent precedences (Tight: not at all).
enum class VolumeMargin { Conservative, Tight };

// PSV of `face` (convex, CCW seen from the front of `facePlane`) from `light`
// (convex). nullopt when no part of the light lies in front of the face's plane
// (a back face casts no shadow for this light).
std::optional<PenumbraVolume> penumbraVolume(const Polygon3& face, const Plane& facePlane,
                                             const Polygon3& light, const Tolerance& tolerance,
                                             VolumeMargin margin = VolumeMargin::Conservative);

}  // namespace penumbra
