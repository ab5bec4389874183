// The critical surfaces of a shadow as wedges, and their pieces on a receiver: shared by
// castShadow (one occluder face) and castObjectShadow (one closed convex object).
// Pure functions and a plain collector; thread-safe per instance.
#pragma once

#include <functional>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/geom/convex2d.h"
#include "core/geom/plane.h"
#include "core/geom/plane_frame.h"
#include "core/geom/tolerance.h"
#include "core/shadow/single_shadow.h"

namespace penumbra {

// The polygon without duplicate vertices and without vertices within eps of the line
// through their neighbours (a flat corner would generate EV wedges that are no
// discontinuity); empty if fewer than 3 corners are left.
Polygon3 withoutFlatCorners(Polygon3 polygon, double eps);

// A critical surface: the cone at `apex` spanned by d1, d2, in `plane`. VE (light
// vertex s, occluder edge ab): apex s, d1 = a − s, d2 = b − s (the part beyond ab
// is the part behind the occluder). EV (light edge pq, occluder vertex v): apex v,
// d1 = v − p, d2 = v − q (rays through v continue behind it).
struct Wedge {
  ElementRef lightElement, occluderElement;
  bool vertexEdge = false;  // VE; else EV
  Vec3 apex{0.0}, d1{0.0}, d2{0.0};
  Plane plane;              // normal d1 × d2
  Vec3 lightPoints[2];      // the generating light vertex (twice) or edge end points
  Vec3 occluderPoints[2];   // the generating occluder edge end points or vertex (twice)
};

// The VE wedge (light vertex s, occluder edge ab) / the EV wedge (light edge pq,
// occluder vertex v); nullopt when the apex lies within eps of the other element's line.
std::optional<Wedge> vertexEdgeWedge(ElementRef lightVertex, ElementRef occluderEdge, const Vec3& s,
                                     const Vec3& a, const Vec3& b, double eps);
std::optional<Wedge> edgeVertexWedge(ElementRef lightEdge, ElementRef occluderVertex, const Vec3& p,
                                     const Vec3& q, const Vec3& v, double eps);

// The chord the wedge's cone cuts across `base` (a convex CCW region of the receiver's
// plane, in `frame`), or nullopt.
std::optional<std::pair<Vec2, Vec2>> wedgeChord(const Wedge& w, const Polygon2& base,
                                                const PlaneFrame& frame, const Tolerance& tolerance);

// Whether `polygon` (the receiver's outline in 3D, a superset of any `base` given to
// wedgeChord) lies wholly more than 2·eps on one side of the wedge's plane: then the plane's
// trace misses base by more than eps in 2D (a 2D distance is the 3D one over the trace's tilt
// ≤ 1) and wedgeChord would give nullopt. A cheap cull before it: small receivers (a model's
// own faces) meet few of a mesh's thousands of silhouette wedges.
bool wedgePlaneMisses(const Wedge& w, const Polygon3& polygon, double eps);
// The same for the wedge vertexEdgeWedge / edgeVertexWedge would make from (apex, d1, d2)
// (s, a − s, b − s / v, v − p, v − q), before it is made: most of a mesh's silhouette wedges
// miss a small receiver, and each made wedge is a copy of some 200 bytes.
bool wedgePlaneMisses(const Vec3& apex, const Vec3& d1, const Vec3& d2, const Polygon3& polygon, double eps);

// The parameter interval of a→b running along the boundary of a convex polygon
// (collinear with some edges within eps), as the hull over those edges.
std::optional<std::pair<double, double>> alongBoundary(const Polygon2& polygon, const Vec2& a,
                                                       const Vec2& b, double eps);

// A shadow's segments as they are found: each chord is split into its parts along the
// penumbra (kind Penumbra), along the umbra (Umbra) and the rest (Internal, kept only
// when asked); pieces along the receiver's own boundary (already in its tree), no
// longer than eps, or equal to an earlier piece of the same kind are dropped. Past
// kIndexFrom kept segments the earlier ones are found through a grid of their ends (a
// whole mesh's shadow has thousands: a scan over them all made keeping quadratic).
class SegmentCollector {
 public:
  SegmentCollector(const Polygon2& receiver, const Polygon2& penumbra, const Polygon2& umbra, double eps)
      : receiver_(receiver), penumbra_(penumbra), umbra_(umbra), eps_(eps) {}
  // A chord a→b of a wedge with these elements; its inner parts are kept iff keepInner()
  // (asked only when there are some).
  void add(const Vec2& a, const Vec2& b, ElementRef lightElement, ElementRef occluderElement,
           const std::function<bool()>& keepInner);
  // A whole chord of one kind (a contact line), not split.
  void addWhole(const Vec2& a, const Vec2& b, SegmentKind kind, ElementRef lightElement,
                ElementRef occluderElement);
  std::vector<CriticalSegment> take() { return std::move(segments_); }

 private:
  void keep(const CriticalSegment& segment);
  // Whether a kept segment of the same kind has the same ends within eps.
  bool keptAlready(const CriticalSegment& segment) const;
  uint64_t cellKey(const Vec2& p, int dx, int dy) const;
  void index(uint32_t segment);

  static constexpr size_t kIndexFrom = 32;
  const Polygon2& receiver_;
  const Polygon2& penumbra_;
  const Polygon2& umbra_;
  double eps_;
  std::vector<CriticalSegment> segments_;
  // Grid cells of side 2·eps → the kept segments with an end in them (both ends listed).
  std::unordered_map<uint64_t, std::vector<uint32_t>> byCell_;
};

}  // namespace penumbra
