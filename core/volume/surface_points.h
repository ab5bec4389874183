// A coarse preview of a volume's isosurface (the page draws it as a point cloud): the grid
// sampled every `stride` voxels, and per coarse cell the field crosses, the mean of its edges'
// crossings (linear along each edge, as surface nets place vertices). Not the traced surface:
// a sketch of where it is. Free function on const data; thread-safe.
#pragma once

#include <vector>

#include "core/geom/vec.h"
#include "core/volume/scalar_volume.h"

namespace penumbra::volume {

struct SurfacePoints {
  int stride = 1;             // voxels between samples
  std::vector<Vec3> points;   // object space (objectFromVoxel applied)
  std::vector<Vec3> normals;  // object space, towards larger values (unit; 0 if flat)
};

// At most `maxCellsPerSide` coarse cells along the longest side (stride chosen from it).
SurfacePoints surfacePoints(const ScalarVolume& data, double isovalue, int maxCellsPerSide = 48);

}  // namespace penumbra::volume
