// Which critical surfaces of a closed convex occluder can be discontinuities at all.
// Pure; thread-safe.
//
// The light a point p sees past a convex solid C is the light minus C's projection
// from p, a convex polygon spanned by the *silhouette* of C seen from p. A VE surface
// (light vertex s, edge e of C) holds the points p for which s, e and p are coplanar;
// e's silhouette status is the same from s and from p (both lie in one plane through
// e, on opposite sides of it), so where s is strictly in front of every face through
// e, e's projection from p lies inside C's projection and crossing the surface
// changes nothing p sees: it is no discontinuity. Likewise an EV surface (light edge
// pq, vertex v of C): the ray from p through v meets pq, and v is on the silhouette
// from p iff it is from that light point, so where p and q are both strictly in
// front of every face through v, the surface is none. Faces are decided by C's own
// face planes (for a convex solid the faces through a boundary point are exactly those
// whose planes contain it), so no adjacency is needed and imported meshes with split
// faces or T-vertices are judged alike.
#pragma once

#include <initializer_list>
#include <span>

#include "core/geom/tolerance.h"
#include "core/scene/scene.h"

namespace penumbra {

class ConvexSilhouette {
 public:
  // `objectFaces`: every world face of one closed convex object (Scene::facesOfObject).
  ConvexSilhouette(std::span<const Face> objectFaces, const Tolerance& tolerance)
      : faces_(objectFaces), tolerance_(tolerance) {}

  // False only when at least two of the object's faces pass through all of
  // `occluderPoints` (an edge's two end points, or one vertex) and every light point
  // lies strictly (beyond Tolerance::onPlane()) in front of each of them: the element
  // is then on no silhouette seen from those light points. Points on a single face (an
  // edge made by clipping the occluder) and light points on or near a plane keep the
  // surface: the test errs only towards keeping lines.
  bool mayBeSilhouette(std::initializer_list<Vec3> occluderPoints,
                       std::initializer_list<Vec3> lightPoints) const;

 private:
  std::span<const Face> faces_;
  Tolerance tolerance_;
};

}  // namespace penumbra
