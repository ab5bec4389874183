#include "core/mesh/receiver_mesh_builder.h"

#include <cmath>

namespace penumbra {

uint32_t ReceiverMeshBuilder::vertex(const Vec2& at, const VertexIrradiance& value) {
  const uint32_t where = location(at);
  // The same value bit for bit (== on each channel: +0 and -0 alike, NaN never) and class.
  for (uint32_t id = firstVertexAt_[where]; id != kNone; id = nextVertexAt_[id - base_])
    if (mesh_.irradiance[id].x == value.irradiance.x && mesh_.irradiance[id].y == value.irradiance.y &&
        mesh_.irradiance[id].z == value.irradiance.z && mesh_.classes[id] == value.lightClass)
      return id;
  const uint32_t id = uint32_t(mesh_.positions.size());
  mesh_.positions.push_back(frame_.to3D(locations_[where]));
  mesh_.irradiance.push_back(value.irradiance);
  mesh_.classes.push_back(value.lightClass);
  // Appended at the chain's end, so earlier vertices are found first (any match is unique anyway).
  nextVertexAt_.push_back(kNone);
  uint32_t* link = &firstVertexAt_[where];
  while (*link != kNone) link = &nextVertexAt_[*link - base_];
  *link = id;
  return id;
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
      const Chain* bucket = buckets_.find(x + dx, y + dy);
      if (!bucket) continue;
      for (uint32_t id = bucket->first; id != kNone; id = nextInBucket_[id])
        if (glm::length(locations_[id] - at) <= eps_) return id;
    }
  const uint32_t id = uint32_t(locations_.size());
  locations_.push_back(at);
  nextInBucket_.push_back(kNone);
  firstVertexAt_.push_back(kNone);
  const auto [bucket, added] = buckets_.tryEmplace(x, y, Chain{id, id});
  if (!added) {
    nextInBucket_[bucket->last] = id;
    bucket->last = id;
  }
  return id;
}

}  // namespace penumbra
