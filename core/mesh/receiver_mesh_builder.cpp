#include "core/mesh/receiver_mesh_builder.h"

#include <cmath>

namespace penumbra {

uint32_t ReceiverMeshBuilder::vertex(const Vec2& at, const VertexIrradiance& value) {
  const Key key{location(at), value.irradiance.x, value.irradiance.y, value.irradiance.z, value.lightClass};
  const auto [it, added] = index_.emplace(key, uint32_t(mesh_.positions.size()));
  if (added) {
    mesh_.positions.push_back(frame_.to3D(locations_[key.location]));
    mesh_.irradiance.push_back(value.irradiance);
    mesh_.classes.push_back(value.lightClass);
  }
  return it->second;
}

// Buckets of side 2·eps: a point merges with the first earlier one within eps.
uint32_t ReceiverMeshBuilder::location(const Vec2& at) {
  const double side = 2 * eps_;
  const long x = long(std::floor(at.x / side)), y = long(std::floor(at.y / side));
  // A neighbour bucket farther than 1.25·eps along an axis holds no point within
  // eps: skipping it finds the same first match, with ~5 look-ups instead of 9.
  const double fx = at.x - double(x) * side, fy = at.y - double(y) * side;
  const long xFrom = fx > 1.25 * eps_ ? 0 : -1, xTo = side - fx > 1.25 * eps_ ? 0 : 1;
  const long yFrom = fy > 1.25 * eps_ ? 0 : -1, yTo = side - fy > 1.25 * eps_ ? 0 : 1;
  for (long dx = xFrom; dx <= xTo; ++dx)
    for (long dy = yFrom; dy <= yTo; ++dy) {
      const auto bucket = buckets_.find({x + dx, y + dy});
      if (bucket == buckets_.end()) continue;
      for (uint32_t id : bucket->second)
        if (glm::length(locations_[id] - at) <= eps_) return id;
    }
  const uint32_t id = uint32_t(locations_.size());
  locations_.push_back(at);
  buckets_[{x, y}].push_back(id);
  return id;
}

}  // namespace penumbra
