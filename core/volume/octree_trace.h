// First ray–isosurface hit in an octree volume: recursive front-to-back traversal of the
// octree (Appendix C) pruned by its embedded min/max tree, caps and scalar leaves walked down
// to cells, cell corners from the cap or by neighbour finding. Read-only; thread-safe.
#pragma once

#include <cstdint>
#include <optional>

#include "core/volume/octree_volume.h"
#include "core/volume/volume_ray.h"

namespace penumbra::volume {

struct TraceCounters {
  uint64_t nodes = 0;       // interior nodes entered
  uint64_t cells = 0;       // cells whose corners were fetched
  uint64_t cubics = 0;      // cells that straddled the isovalue (root finder run)
  uint64_t neighbours = 0;  // corner voxels found by neighbour finding
};

// The first hit along the ray in [ray.tMin, ray.tMax] ∩ the box [0, size − 1]³, or nullopt.
template <class T>
std::optional<VolumeHit> traceOctree(const OctreeVolume<T>& volume, const VolumeRay& ray,
                                     double isovalue, TraceCounters* counters = nullptr);

}  // namespace penumbra::volume
