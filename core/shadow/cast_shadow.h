// Casting one occluder face on one receiver face from one light (paper §2.3):
// penumbra/umbra regions and the VE/EV discontinuity segments. Pure functions; thread-safe.
#pragma once

#include <cstddef>
#include <optional>

#include "core/geom/plane_frame.h"
#include "core/scene/scene.h"
#include "core/shadow/single_shadow.h"

namespace penumbra {

// The light and occluder as they matter for one (light, occluder, receiver):
//   light    S' = light polygon ∩ front of R's plane ∩ front of O's plane
//                 (O blocks only light points strictly in front of it);
//   occluder O' = O ∩ front of R's plane ∩ front of the light's plane
//                 (a face touching or piercing R keeps its part in front: the
//                 D0 contact edge is then an edge of O' lying in R's plane).
// Both keep their input winding (S' CCW from the light's front, O' CCW from O's
// front), with duplicate and collinear vertices removed. ElementRef indices in a
// SingleShadow refer to these polygons: vertex i, edge i = vertex i → i+1.
struct CastingPair {
  Polygon3 light;
  Polygon3 occluder;
};
std::optional<CastingPair> castingPair(const Scene& scene, size_t light, const Face& occluder,
                                       const Face& receiver);

// Whether some vertex of `occluder` lies more than the length tolerance in front of
// `receiver`'s plane. Without one, O' is empty: castShadow casts nothing, whatever the light.
bool reachesFrontOf(const Face& occluder, const Face& receiver, const Tolerance& tolerance);

// What `occluder` casts on `receiver` from light `light`, in `receiverFrame`
// (PlaneFrame::onPlane(receiver.plane, receiver.polygon[0])), or nullopt when
// nothing of R is shadowed (R not behind O's plane, empty S' or O', or a
// penumbra with no area on R).
//
// Regions are intersections of closed half-planes on R's plane, clipped to
// R ∩ front of the light's plane ∩ behind O's plane (so unbounded shadows are fine):
//   penumbra: the separating planes through (S' vertex, O' edge) and (S' edge, O'
//             vertex), O' on their front;
//   umbra:    every plane through (S' vertex, O' edge), O' on its front (empty if
//             S' touches O's plane: those light points are never blocked).
// Segments: each VE wedge (rays from S' vertex s through O' edge e beyond e) and
// EV wedge (rays from S' edge f through O' vertex v beyond v) cut by R's plane,
// inside R. Kinds: Contact on the line where O' meets R's plane (emitted once per
// contact edge, with light vertex = the first S' vertex that generates it);
// Penumbra / Umbra where it runs along that polygon's boundary (a segment partly
// along the umbra is split, the rest Internal, all pieces keeping their elements);
// else Internal. Dropped: pieces shorter than the length tolerance, pieces along
// R's own boundary, pieces equal to an earlier one (same end points and kind).
// Collinear overlapping pieces from different elements are kept (EE coincidences,
// e.g. parallel light and occluder edges, put four wedges in one plane).
//
// With `silhouetteOnly`, an occluder of a closed convex object (Scene::isClosedConvex)
// keeps the Internal pieces of a surface only if its element may lie on the object's
// silhouette from the light element (convex_silhouette.h): the rest are no
// discontinuity of the object's shadow. Region edges and contacts are always kept.
std::optional<SingleShadow> castShadow(const Scene& scene, size_t light, const Face& occluder,
                                       const Face& receiver, const PlaneFrame& receiverFrame,
                                       bool silhouetteOnly = true);

}  // namespace penumbra
