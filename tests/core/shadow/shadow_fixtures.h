// Test helpers for core/shadow: tiny scenes holding one light, one occluder face
// and one receiver face; sampling on a receiver; truth checks against ExactReference.
#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "core/geom/convex2d.h"
#include "core/geom/plane_frame.h"
#include "core/scene/scene.h"
#include "core/shadow/single_shadow.h"

namespace penumbra::testing {

// A scene with exactly one light and two single-face objects: occluder (face 0),
// receiver (face 1).
struct Tiny {
  Scene scene;
  const Face& occluder() const { return scene.faces()[0]; }
  const Face& receiver() const { return scene.faces()[1]; }
  PlaneFrame frame() const { return PlaneFrame::onPlane(receiver().plane, receiver().polygon[0]); }
};
Tiny makeTiny(const Light& light, const Polygon3& occluder, const Polygon3& receiver);

Light squareLight(const Vec3& centre, double half, const Vec3& front);
// The polygon's vertices reordered so it is CCW seen from `front`.
Polygon3 facing(Polygon3 polygon, const Vec3& front);

// Signed distance from a convex CCW polygon's boundary: positive inside.
// -infinity for an empty polygon.
double signedDistance(const Polygon2& polygon, const Vec2& p);

struct RegionCounts {
  int samples = 0;
  int penumbra = 0;  // checked inside the penumbra (margin away), umbra excluded
  int umbra = 0;     // checked inside the umbra
  int outside = 0;   // checked outside the penumbra
  int mismatches = 0;
};

// Samples points on the receiver (half uniform on it, half near the penumbra) and
// compares the computed regions with ExactReference on the tiny scene. Points
// within `margin` of a region boundary are not judged.
RegionCounts checkRegions(const Tiny& tiny, const std::optional<SingleShadow>& shadow,
                          std::mt19937_64& rng, int samples, double margin,
                          const std::string& label);

// Checks every segment against its generating elements (VE/EV coplanarity and ray
// crossing; contact on the occluder edge) and against the regions. Returns the
// number of violations (each reported with ADD_FAILURE).
int checkSegments(const Tiny& tiny, const SingleShadow& shadow, std::mt19937_64& rng,
                  const std::string& label);

}  // namespace penumbra::testing
