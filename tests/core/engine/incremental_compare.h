// Test helpers for the incremental engine: comparing two engines' DM meshes of the
// same scene (vertex values at the same points, classes at points, discontinuity
// segments up to splitting) and generating random edit frames on cube scenes.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "core/engine/engine.h"

namespace penumbra::testing {

// The mean of the polygon's vertices.
Vec3 centroid(const Polygon3& polygon);
// The polygon scaled by `scale` about its centroid and moved by `by`.
Polygon3 scaledMoved(const Polygon3& polygon, double scale, const Vec3& by);
// A move of object `id` by `by` from where it is in the engine's scene.
Edit moveEditBy(const Engine& engine, const std::string& id, const Vec3& by);

struct EngineDiff {
  size_t vertices = 0;        // vertices compared, both directions
  size_t matchedVertices = 0; // of those, with a vertex of the other engine at the same point
  size_t valueErrors = 0;
  // Vertices where the two disagree but `a` equals the exact reference and `b` does
  // not (the rebuild's own precision, e.g. backprojection order): not `a`'s error.
  size_t secondOffReference = 0;
  size_t pointsCompared = 0;
  size_t classErrors = 0;
  size_t segmentSamples = 0;
  size_t segmentErrors = 0;
  size_t receiverErrors = 0;  // receivers present in one engine only
  std::string firstProblem;
  size_t errors() const { return valueErrors + classErrors + segmentErrors + receiverErrors; }
};

// Compares `a` and `b` (same scene): (a) every DM vertex of each has the other's value
// at its point (the lists around the other's vertex there, else of its cell holding
// the point, lit at exactly that point), within 1e-9 relative + 1e-12 of `peak`, or
// else `a` has the exact reference's value there and `b` not (counted apart); (b) `randomPoints` seeded points lit from
// each engine's cell get the same class and value; (c) every non-orphan node segment
// of each lies on edges of the other, or in the other's umbra of its light (sampled).
EngineDiff compareEngines(const Engine& a, const Engine& b, double peak, size_t randomPoints, uint64_t seed);

// The largest vertex irradiance (red channel) of an engine.
double peakIrradiance(const Engine& engine);

// Moves object `id` to `transform` in one frame, validates the engine, then compares it with
// a fresh build of its scene (compareEngines, 200 points seeded by `seed`): "incremental ≡
// rebuild" after one move.
struct MoveCheck {
  FrameResult frame;
  EngineDiff diff;
};
MoveCheck moveAndCompareWithRebuild(Engine& engine, const std::string& id, const Transform& transform,
                                    uint64_t seed);

// A random frame of `edits` edits (move: small/large translations, rotations about
// y, resting on or touching/piercing another object; add: a new cube on the floor or
// on a cube; remove) on the generated cubes scene held by `engine`.
Frame randomFrame(const Engine& engine, std::mt19937_64& rng, size_t edits, int& nextNewId);

// A random light edit on a generated cubes scene: add a smaller copy of a light moved across
// the ceiling (id lamp_N), remove a light (when there are two or more), move one, or give
// one a new radiance (or both).
Edit randomLightEdit(const Scene& scene, std::mt19937_64& rng, int& nextLightId);
// A frame of one random light edit and `objectEdits` random object edits, in random order.
Frame randomLightFrame(const Engine& engine, std::mt19937_64& rng, size_t objectEdits,
                       int& nextNewId, int& nextLightId);

}  // namespace penumbra::testing
