// Casting a closed convex object as one occluder (issue 11, item 5): its shadow on a
// receiver from its silhouette, not face by face. Pure functions; thread-safe.
//
// The light a point x sees past a convex solid O is the light minus O's central
// projection from x, a convex polygon spanned by O's silhouette seen from x. So, for a
// light S' (the light clipped to the receiver's front) and O wholly in front of both the
// receiver's and the light's planes:
//   penumbra: x in front of every plane that separates O from S' (O on its front),
//             through a light vertex and an edge of O or a light edge and a vertex of O
//             (a superset of the points O shadows: a segment s→x through O crosses no
//             separating plane from O's side, so nothing O shadows is left out);
//   umbra:    x in the cone from every light vertex s over O: behind every plane through
//             s and an edge of O that supports O (the planes through s's silhouette
//             edges); all light vertices hidden means the whole convex light is;
//   segments: VE surfaces (light vertex s, edge e) with e on O's silhouette from s
//             (the plane through them supports O), and EV surfaces (light edge pq,
//             vertex v) unless p and q lie strictly on one side (front or back) of every
//             face through v: then v is on no silhouette from the edge, nor from any
//             receiver point on the surface (the two lie on opposite sides of v).
// Every other VE/EV surface of O's faces is no discontinuity of what a receiver point sees.
// The faces' own penumbra and umbra boundaries, which cast face by face cut a receiver into
// hundreds of cells under a tessellated object, are not lines of O's shadow at all.
//
// Any other mesh M (closed or open, convex or not; Scene::meshTopology), issue 35:
//   penumbra: that of M's axis-aligned box B ⊇ M, as above (a superset of M's);
//   umbra:    none (M's umbra is not convex; no cell is culled or called umbra by it);
//   segments: VE (light vertex s, edge e) unless e is *regular* (two faces running it in
//             opposite directions) and s lies strictly on one side (front or back) of both
//             faces' planes; EV (light edge pq, corner v) over the stretch of pq from
//             whose points v may be on the silhouette: for a corner whose edges are all
//             regular, not where every face through v has the point strictly in front
//             (or every one strictly behind); each face's side changes once along pq, so
//             the stretch is the hull of what those two intervals leave.
// Rule: an irradiance discontinuity on the receiver is where a VE/EV surface is tangent
// to M's silhouette seen from a light point. Seen from s, a regular edge whose two faces
// both face s (or both face away) is no silhouette edge: the surface folds only where
// one face turns towards s and the other away. Points x on the receiver on the surface
// through s and e see e from the other side of the plane (s, e) (the segment s→x crosses
// e), so e is a silhouette edge from x exactly when it is from s, and the rays near s→x
// meet M's surface on both sides of e alike: crossing the line changes nothing x sees. A
// corner with all its faces on one side from both ends of pq is so for every point of
// pq (half-spaces are convex), and the same holds point by point along pq. Edges that are not regular (open boundaries, non-manifold
// or inconsistently oriented edges) are always kept. Every test errs towards keeping a
// line. EEE surfaces (three edges, quadric) are left out as the paper leaves them out:
// vertices stay exact (backprojection does not use the lines), only cells may hold a
// value discontinuity along such a curve inside them.
#pragma once

#include <cstddef>
#include <optional>

#include "core/geom/plane_frame.h"
#include "core/scene/scene.h"
#include "core/shadow/single_shadow.h"

namespace penumbra {

// Whether object `handle` casts on `receiver` from light `light` as one occluder: it is
// closed convex (Scene::isClosedConvex) or has a mesh (Scene::meshTopology), each vertex
// of the solid (of the mesh's box) lies more than onPlane() in front of the receiver's
// plane and of the light's plane (no contact line, no light point inside or behind it).
// Otherwise its faces cast one by one
// (castShadow): a mesh on its own faces (self-shadowing) always does.
bool castsAsOneOccluder(const Scene& scene, size_t light, uint32_t handle, const Face& receiver);

// Whether mesh `handle` (Scene::meshTopology, not closed convex) casts whole on those of its
// own faces that have a corner in front of them: its box lies farther than onPlane() in
// front of the light's plane.
bool castsWholeOnItself(const Scene& scene, size_t light, uint32_t handle);

// The occluder a candidate face casts as: wholeObject(face.object) if `wholeObjects` and
// castsAsOneOccluder, else the face itself.
FaceId castingOccluder(const Scene& scene, size_t light, FaceId face, const Face& receiver, bool wholeObjects);

// What object `handle` casts on `receiver` from light `light` (castsAsOneOccluder must
// hold), in `frame`, with occluder wholeObject(handle); nullopt when it shadows nothing of
// the receiver. Element refs: light vertices and edges of the clipped light; the object's
// unique vertices (Kind::Vertex, sorted by position) and edges (Kind::Edge, by vertex pair).
// A mesh's contact lines (where it meets the receiver's plane: resting on a floor, or its own
// section on its own faces) are looked for among the faces within `contactReach` · the scene's
// size of the receiver (kContactReach; a pass over every face for each receiver was quadratic):
// a contact edge's chord is the edge itself up to its onPlane offset from the plane, so a face
// farther off adds nothing unless a light vertex lies within ~1e-4 (relative) of the receiver's
// plane. The silhouette's edges and corners are looked at only where they lie in the shaft
// between the light and the receiver (their hull, core/geom/shaft.h; object_shadow.cpp says
// why nothing outside it reaches the receiver). Infinity looks at every face and every
// silhouette item (tests/core/shadow/contact_reach_test.cpp compares).
constexpr double kContactReach = 0.01;
std::optional<SingleShadow> castObjectShadow(const Scene& scene, size_t light, uint32_t handle,
                                             const Face& receiver, const PlaneFrame& frame,
                                             double contactReach = kContactReach);

}  // namespace penumbra
