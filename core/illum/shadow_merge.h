// Shadows of one closed convex object from one point, merged into one convex polygon.
// Free functions on a const Scene and plain buffers; thread-safe.
//
// Why it is exact: from p, the faces of a convex solid K that block p (p behind their
// planes) tile K's central projection onto the light's plane, and with K wholly in front
// of that plane the projection of K's part between p and the plane is convex. So the
// union of those faces' shadows is the convex hull of their corners; a listed face left
// out (it hides no area from p) or clipped away only shrinks the hull inside that
// projection, which covers the light no more than the faces do. One polygon of ~6 edges
// instead of up to three quads per box (hundreds of faces for a sphere) is what the
// boundary kernel (VisibleContour, O(edges × shadows)) then clips.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "core/geom/convex2d.h"
#include "core/geom/plane.h"
#include "core/scene/scene.h"

namespace penumbra {

// Whether object `handle`'s shadows from p may be merged: it is closed convex, every
// vertex lies more than tolerance().length() in front of the light's plane (no light
// point inside it), and p is farther than onPlane() from every face's plane (the
// single-sided rule then decides each face the same way as the solid).
bool mergeableShadows(const Scene& scene, uint32_t handle, const Plane& lightPlane, const Vec3& p);
// The rule's two tests, for a caller that has the distances already (Backprojection): a
// corner's height over the light's plane, and a face's plane's signed distance from p.
inline bool mergeableCorner(double height, const Tolerance& tolerance) { return height > tolerance.length(); }
inline bool mergeableFaceSide(double side, const Tolerance& tolerance) { return std::abs(side) > tolerance.onPlane(); }

// The convex hull of `points`, counter-clockwise, into `out` (strict turns only, points
// within `eps` of the previous hull corner dropped). Fewer than 3 corners: no area.
void convexHullInto(std::span<const Vec2> points, double eps, std::vector<Vec2>& out);

// Shadows (points[starts[i], starts[i+1]), convex CCW) with their groups (an object
// handle, or kNoGroup): each group of two or more shadows is replaced, at its first
// shadow's place, by the hull of their corners; the rest are copied. Into outPoints /
// outStarts (outStarts[0] = 0). Returns whether anything was merged.
inline constexpr uint32_t kNoGroup = 0xffffffffu;
bool mergeShadowGroups(std::span<const Vec2> points, std::span<const uint32_t> starts,
                       std::span<const uint32_t> groups, double eps, std::vector<Vec2>& outPoints,
                       std::vector<uint32_t>& outStarts);

}  // namespace penumbra
