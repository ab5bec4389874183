// Refining one display piece's triangles until linear interpolation between their corners is
// within a tolerance of the exact direct light (docs/DESIGN.md "Error-bounded display mesh").
// Every decision is one edge's or one triangle's: an edge is halved when the exact value at
// its midpoint is off the mean of its ends, a triangle gets its centroid when the value there
// is off the mean of its corners, each by more than tolerance × the light's local unshadowed
// level. An outline edge's decision depends on the edge alone, so the two pieces (or cells)
// sharing it split it alike and the mesh stays free of T-junctions; an inner edge is also left
// whole while a triangle on it is thinner than minEdge / 8 (the shape limit: repeated halving
// along one edge would make slivers). Pure function of its inputs; thread-safe.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/geom/vec.h"
#include "core/illum/vertex_illumination.h"

namespace penumbra {

struct RefineSettings {
  double tolerance = 0;   // relative to each light's local unshadowed level; 0: no refinement
  double minEdge = 0;     // edges no longer than this are not halved
  uint32_t maxPoints = 0; // a piece's points (its loop, centre and added points) at most
  bool operator==(const RefineSettings&) const = default;
};

// A piece's triangulation being refined: points (loop first) with each light's value and
// unshadowed level, and triangles of local indices, counter-clockwise.
struct PieceRefinement {
  size_t lights = 0;
  std::vector<Vec2> points;
  std::vector<VertexLight> values;  // points × lights
  std::vector<double> levels;       // points × lights; NaN: not known yet (asked when needed)
  std::vector<std::array<uint32_t, 3>> triangles;
  bool capped = false;  // maxPoints stopped a refinement the tolerance asked for
  size_t asked = 0;     // points whose values refinePiece asked of the evaluator (kept or not)
};

// The exact per-light values at a point of the piece as its cell sees it, appended to `values`.
using PointEvaluator = std::function<void(const Vec2& q, std::vector<VertexLight>& values)>;
// Each light's unshadowed level at q (what it gives with nothing in the way), appended to
// `levels`. Asked only where a test is not decided without it: the level is at least the
// visible factor, and equals it where the light is wholly seen (LightClass::Lit).
using LevelEvaluator = std::function<void(const Vec2& q, std::vector<double>& levels)>;

// Refines `piece` in place: rounds of (decide every edge and, for triangles with no edge
// halved, the centroid; split the triangles by the pattern of their halved edges) until
// nothing fails, no edge is long enough, or the next round would pass maxPoints (capped).
// Returns whether any point was added.
bool refinePiece(PieceRefinement& piece, const RefineSettings& settings, const PointEvaluator& evaluate,
                 const LevelEvaluator& level);

}  // namespace penumbra
