// The vertices of one receiver's display mesh as cells hand in (point, value) pairs: points
// within eps are one location, repeated once per distinct value. Used by one thread at a time.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/geom/plane_frame.h"
#include "core/illum/vertex_illumination.h"
#include "core/mesh/mesh.h"

namespace penumbra {

// Points within eps are one location (lattice cuts of a shared edge come from each side), and a
// location repeats once per distinct value (value discontinuities, dark cells). Ids are given in
// order of first appearance, so the output depends only on the sequence of calls.
class ReceiverMeshBuilder {
 public:
  // Appends to `mesh`; `mesh` and `frame` must outlive the builder.
  ReceiverMeshBuilder(ReceiverMesh& mesh, const PlaneFrame& frame, double eps)
      : mesh_(mesh), frame_(frame), eps_(eps) {}

  // The id of the output vertex at `at` with `value`, added to the mesh on first sight.
  uint32_t vertex(const Vec2& at, const VertexIrradiance& value);

 private:
  struct Key {
    uint32_t location;
    double r, g, b;
    LightClass lightClass;
    bool operator==(const Key& o) const {
      return location == o.location && r == o.r && g == o.g && b == o.b && lightClass == o.lightClass;
    }
  };
  // Hashes agree with ==: +0 and -0 hash alike.
  static size_t mix(size_t seed, size_t value) { return seed ^ (value + 0x9e3779b97f4a7c15ull + (seed << 6) + (seed >> 2)); }
  static size_t bits(double x) { return std::hash<double>{}(x == 0 ? 0.0 : x); }
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return mix(mix(mix(mix(k.location, bits(k.r)), bits(k.g)), bits(k.b)), size_t(k.lightClass));
    }
  };
  struct BucketHash {
    size_t operator()(const std::pair<long, long>& b) const { return mix(std::hash<long>{}(b.first), std::hash<long>{}(b.second)); }
  };

  // Buckets of side 2·eps: a point merges with the first earlier one within eps.
  uint32_t location(const Vec2& at);

  ReceiverMesh& mesh_;
  const PlaneFrame& frame_;
  double eps_;
  std::vector<Vec2> locations_;
  std::unordered_map<std::pair<long, long>, std::vector<uint32_t>, BucketHash> buckets_;
  std::unordered_map<Key, uint32_t, KeyHash> index_;
};


}  // namespace penumbra
