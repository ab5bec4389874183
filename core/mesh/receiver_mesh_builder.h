// The vertices of one receiver's display mesh as cells hand in (point, value) pairs: points
// within eps are one location, repeated once per distinct value. Used by one thread at a time.
#pragma once

#include <cstdint>
#include <vector>

#include "core/geom/plane_frame.h"
#include "core/illum/vertex_illumination.h"
#include "core/mesh/bucket_table.h"
#include "core/mesh/mesh.h"

namespace penumbra {

// Points within eps are one location (lattice cuts of a shared edge come from each side), and a
// location repeats once per distinct value (value discontinuities, dark cells). Ids are given in
// order of first appearance, so the output depends only on the sequence of calls.
class ReceiverMeshBuilder {
 public:
  // Appends to `mesh`; `mesh` and `frame` must outlive the builder.
  ReceiverMeshBuilder(ReceiverMesh& mesh, const PlaneFrame& frame, double eps)
      : mesh_(mesh), frame_(frame), eps_(eps), base_(uint32_t(mesh.positions.size())) {}

  // The id of the output vertex at `at` with `value`, added to the mesh on first sight.
  uint32_t vertex(const Vec2& at, const VertexIrradiance& value);

 private:
  // The locations of a bucket, in order of appearance: a chain through nextInBucket_.
  struct Chain {
    uint32_t first, last;
  };
  static constexpr uint32_t kNone = 0xffffffffu;

  // Buckets of side 2·eps: a point merges with the first earlier one within eps.
  uint32_t location(const Vec2& at);

  ReceiverMesh& mesh_;
  const PlaneFrame& frame_;
  double eps_;
  uint32_t base_;  // the mesh's vertex count before this builder
  std::vector<Vec2> locations_;
  std::vector<uint32_t> nextInBucket_;  // per location
  BucketTable<Chain> buckets_;
  // Per location, its first output vertex; per output vertex (from base_), the next one at its
  // location.
  std::vector<uint32_t> firstVertexAt_, nextVertexAt_;
};

}  // namespace penumbra
