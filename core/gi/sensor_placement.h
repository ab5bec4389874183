// Where sensors go (seed 001, "Sensor quantity and distribution", Fig. 7): a sensor at the
// corners of tile × tile tiles; a tile whose four corners lie on one surface and agree within
// `threshold` is filled by bilinear interpolation, any other is split in four, down to single
// pixels. Pixels of a tile that lie on another surface than its corners get their own sensor.
// Deterministic: the same values on any number of threads. Thread-safe (no state).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/geom/vec.h"
#include "core/util/parallel.h"

namespace penumbra::gi {

struct PlacementSettings {
  int tile = 16;            // the first tiles' side in pixels (>= 1)
  double threshold = 0.05;  // largest relative spread of a tile's corners that is interpolated
};

struct PlacementStats {
  size_t sensors = 0;                   // pixels sensed
  size_t interpolated = 0;              // pixels filled from their tile's corners
  std::vector<size_t> sensorsPerLevel;  // level 0: the first tiles' corners; last: stray pixels
};

// Per-pixel values on a width × height image; id[p] < 0: no surface there (value 0, no sensor).
// sense(p) gives a pixel's value and is called concurrently, once per sensed pixel; progress
// (sensors so far) is called every 64 sensors inside a level and after each level, one call at a
// time but from any of the loop's threads; a throw from it ends the placement (a cancel).
std::vector<Vec3> placeSensors(int width, int height, const std::vector<int32_t>& id,
                               const std::function<Vec3(size_t pixel)>& sense, const PlacementSettings& settings,
                               const Parallel& parallel, PlacementStats& stats,
                               const std::function<void(size_t sensors)>& progress = {});

// The relative spread of values: max |v − mean| over the largest channel of the mean (0 when all
// are 0). Used by placeSensors for a tile's corners.
double relativeSpread(const Vec3* values, size_t n);

}  // namespace penumbra::gi
