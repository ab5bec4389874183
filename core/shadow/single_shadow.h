// What one occluder face casts on one receiver face from one light, in the
// receiver's 2D frame: the penumbra and umbra regions (clipped to the receiver)
// and every discontinuity segment with the light/occluder elements that generate
// it. Produced by castShadow (core/shadow), consumed by the DM-tree (core/dmtree).
// Plain data; thread-safe to read.
#pragma once

#include <cstdint>
#include <vector>

#include "core/geom/convex2d.h"
#include "core/scene/scene.h"

namespace penumbra {

// A vertex or an edge of a polygon (edge i runs from vertex i to vertex i+1).
// Indices refer to the light polygon and the occluder polygon *after* the clipping
// castShadow does (documented there), so equal refs mean the same element.
struct ElementRef {
  enum class Kind : uint8_t { Vertex, Edge };
  Kind kind = Kind::Vertex;
  uint32_t index = 0;
  bool operator==(const ElementRef&) const = default;
  auto operator<=>(const ElementRef&) const = default;
};

enum class SegmentKind : uint8_t {
  Penumbra,  // on the outer boundary of the penumbra (lit | penumbra)
  Umbra,     // on the boundary of the umbra (penumbra | umbra)
  Internal,  // an EV or VE discontinuity inside the penumbra
  Contact,   // D0: where the occluder touches or pierces the receiver (value jumps)
};

// A critical surface (light element, occluder element) — VE = (light vertex,
// occluder edge), EV = (light edge, occluder vertex) — cut by the receiver's plane.
struct CriticalSegment {
  Vec2 a{0.0}, b{0.0};  // end points on the receiver (2D frame), a != b
  SegmentKind kind = SegmentKind::Internal;
  ElementRef lightElement;
  ElementRef occluderElement;
};

struct SingleShadow {
  uint32_t light = 0;
  FaceId occluder;
  FaceId receiver;
  Polygon2 penumbra;  // penumbra region ∩ receiver, convex CCW; never empty in a result
  Polygon2 umbra;     // umbra region ∩ receiver, convex CCW; may be empty
  std::vector<CriticalSegment> segments;
  // The umbra hides the whole light at every point of its closure, so the DM-tree may
  // cull later shadows of the light there (DmTree::insert): the occluder lies wholly
  // farther than onPlane() in front of the receiver's plane. Not so where it touches the
  // receiver (on its own plane a face hides nothing), nor for a whole object (a sliver of
  // light near its faces' planes, vertex_illumination.cpp case 2). false: never culls.
  bool cullsBehind = false;
};

}  // namespace penumbra
