// Per-scene resource limits of the engine (EngineSettings::limits) and the running
// totals checked against them. The counters are atomic: receivers may be cast in parallel.
#pragma once

#include <atomic>
#include <cstddef>

#include "core/dmtree/dm_tree.h"
#include "core/geom/resource_limit.h"

namespace penumbra {

// Defaults (README "Degenerate geometry and resource limits"): cubes15 uses ~80 tree
// nodes a face; at that density the 5000-cube bench scene (30,006 faces) needs ~2.4M.
struct ResourceLimits {
  size_t faces = 500'000;              // scene faces
  size_t treeNodes = 50'000'000;       // DM-tree nodes, leaves included, all receivers (also
                                       // caps one light's ordering BSP and any single tree)
  size_t vertices = 25'000'000;        // DM-tree vertices, all receivers
  size_t bytes = size_t(16) << 30;     // approximate bytes of the trees and their vertex values
};

// What one receiver's DM-tree and its per-vertex values (for `lights` lights) hold;
// bytes count slots (dead ones too: they stay allocated).
struct TreeUsage {
  size_t nodes = 0, vertices = 0, bytes = 0;
};
TreeUsage usageOf(const DmTree& tree, size_t lights);

class ResourceBudget {
 public:
  explicit ResourceBudget(const ResourceLimits& limits = {}) : limits_(limits) {}
  ResourceBudget(const ResourceBudget& other) { *this = other; }
  ResourceBudget& operator=(const ResourceBudget& other);

  const ResourceLimits& limits() const { return limits_; }
  // Throws ResourceLimitError if a scene of `faces` faces passes limits().faces.
  void checkFaces(size_t faces) const;
  // One tree went from `before` to `after` (a new tree: before = {}, a dropped one:
  // after = {}): updates the totals, then throws ResourceLimitError if one passes its limit.
  void change(const TreeUsage& before, const TreeUsage& after);
  // Totals to zero (before recounting every tree with change({}, usage)).
  void clear();
  TreeUsage totals() const;

 private:
  ResourceLimits limits_;
  std::atomic<size_t> nodes_{0}, vertices_{0}, bytes_{0};
};

}  // namespace penumbra
