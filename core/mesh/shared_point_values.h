// The exact values at points where cells of one receiver meet, kept for the other cell. Two
// cells with the same occluder list (one interned object) light a point of their common edge
// with the same call on the same numbers, so the second copies the first's values instead of
// computing them again (14 % of the 6,320-triangle teapot's evaluations: an edge whose neighbour
// is a sliver left unrefined, or another list, is asked once). A cell's two pieces on either side
// of a lattice line share its points the same way (3 % more). The values, and so the mesh, stay
// bit for bit the same. A point holds one list's values: asked with another list, it is computed
// as before.
// Thread-safe (shards, a mutex each): the cells of a receiver are lit on several threads.
#pragma once

#include <array>
#include <cstdint>
#include <mutex>
#include <span>
#include <vector>

#include "core/dmtree/occluder_list.h"
#include "core/geom/vec.h"
#include "core/illum/vertex_illumination.h"
#include "core/mesh/bucket_table.h"

namespace penumbra {

class SharedPointValues {
 public:
  explicit SharedPointValues(size_t lights) : lights_(lights) {}

  // Appends the values kept at q for `list` to `out` and returns true; false when none are.
  bool find(const Vec2& q, const OccluderList* list, std::vector<VertexLight>& out);
  // Keeps `values` (one per light) at q for `list`, unless q holds values already.
  void keep(const Vec2& q, const OccluderList* list, std::span<const VertexLight> values);

 private:
  struct Kept {
    const OccluderList* list = nullptr;
    uint32_t row = 0;  // values[row * lights, (row + 1) * lights)
  };
  struct Shard {
    std::mutex mutex;
    BucketTable<Kept> table;  // by q's coordinates' bits
    std::vector<VertexLight> values;
  };
  static constexpr size_t kShards = 64;
  Shard& shardOf(int64_t x, int64_t y);

  size_t lights_;
  std::array<Shard, kShards> shards_;
};

}  // namespace penumbra
