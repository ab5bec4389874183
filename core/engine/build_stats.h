// Counters and timings of one full build of the discontinuity mesh (what
// `penumbra build --stats` prints). Plain value filled by the engine.
#pragma once

#include <cstddef>

namespace penumbra {

struct BuildTimings {
  double ordering = 0;          // seconds: front-to-back orders, all lights
  double cube = 0;              // shadow overlap cubes
  // A receiver is illuminated as soon as its shadows are cast, while others are still casting:
  // the two steps' wall time is split in proportion to the thread time each took.
  double castingAndMerging = 0; // castShadow + DM-tree merges
  double illumination = 0;      // vertex illumination
  double triangulation = 0;     // cells -> triangles (Engine::mesh)
  double total() const { return ordering + cube + castingAndMerging + illumination + triangulation; }
};

struct BuildStats {
  size_t faces = 0;
  size_t receivers = 0;            // faces with a DM-tree (some light reaches their front)
  size_t lights = 0;
  size_t candidatePairs = 0;       // unordered pairs from the overlap cubes, summed over lights
  size_t closedConvexPairs = 0;    // of those, not cast: both faces of one closed convex object
  size_t castAttempts = 0;         // (occluder, receiver, light) castShadow calls
  size_t pairsWithShadow = 0;      // of those, the ones that cast a shadow
  size_t tiles = 0;                // overlap-cube tiles, summed over lights
  size_t orderFragments = 0;       // fragments of the front-to-back orders
  size_t treeNodes = 0;            // splitting nodes of all DM-trees
  size_t cells = 0;
  size_t vertices = 0;             // DM-tree vertices (before per-side copies)
  // Of those, the ones of receivers meshed from their lattice squares, whose values are not
  // computed (Engine::Receiver::fromLattice); the classes and comparisons count the others.
  size_t latticeVertices = 0;
  size_t litVertices = 0, penumbraVertices = 0, umbraVertices = 0;
  size_t comparisons = 0;          // source/occluder comparisons, all lit vertices and lights
  double comparisonsPerVertex() const {
    return vertices > latticeVertices ? double(comparisons) / double(vertices - latticeVertices) : 0;
  }
  BuildTimings seconds;
};

}  // namespace penumbra
