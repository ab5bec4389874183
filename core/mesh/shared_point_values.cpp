#include "core/mesh/shared_point_values.h"

#include <bit>

namespace penumbra {

namespace {

std::pair<int64_t, int64_t> bitsOf(const Vec2& q) {
  return {std::bit_cast<int64_t>(q.x), std::bit_cast<int64_t>(q.y)};
}

}  // namespace

SharedPointValues::Shard& SharedPointValues::shardOf(int64_t x, int64_t y) {
  const uint64_t h = (uint64_t(x) * 0x9e3779b97f4a7c15ull) ^ (uint64_t(y) * 0xc2b2ae3d27d4eb4full);
  return shards_[(h >> 58) % kShards];
}

bool SharedPointValues::find(const Vec2& q, const OccluderList* list, std::vector<VertexLight>& out) {
  if (lights_ == 0) return false;
  const auto [x, y] = bitsOf(q);
  Shard& shard = shardOf(x, y);
  std::lock_guard lock(shard.mutex);
  const Kept* kept = shard.table.find(x, y);
  if (!kept || kept->list != list) return false;
  const auto row = shard.values.begin() + long(kept->row * lights_);
  out.insert(out.end(), row, row + long(lights_));
  return true;
}

void SharedPointValues::keep(const Vec2& q, const OccluderList* list, std::span<const VertexLight> values) {
  if (lights_ == 0 || values.size() != lights_) return;
  const auto [x, y] = bitsOf(q);
  Shard& shard = shardOf(x, y);
  std::lock_guard lock(shard.mutex);
  const uint32_t row = uint32_t(shard.values.size() / lights_);
  if (shard.table.tryEmplace(x, y, Kept{list, row}).second)
    shard.values.insert(shard.values.end(), values.begin(), values.end());
}

}  // namespace penumbra
