// Indirect light baked onto a served version's DM mesh (docs/API.md "Indirect light"): per mesh
// vertex the irradiance gi::vertexIndirect captures, made lazily on the first request for a
// (version, sensor size, bounces) and kept for the newest few. Thread-safe: a bake runs on the
// requesting thread outside the lock, from the immutable snapshot alone (no engine, no edit lock);
// requests for the same bake wait for it, nothing else does.
#pragma once

#include <compare>
#include <cstdint>
#include <deque>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "core/mesh/mesh.h"
#include "server/limits.h"
#include "server/scene_snapshot.h"

namespace penumbra::server {

struct IndirectSettings {
  int sensorSize = kDefaultIndirectSensorSize;  // texels per side of each vertex's sensor
  int bounces = 1;
  auto operator<=>(const IndirectSettings&) const = default;
};

struct IndirectBake {
  uint64_t version = 0;
  IndirectSettings settings;
  Mesh mesh;  // SceneSnapshot::mesh()'s shape; irradiance = the indirect irradiance (W·m⁻²)
  // Per SceneSnapshot::parts index: its receiver's index in `mesh` and its first vertex there.
  std::vector<size_t> partReceiver, partOffset;
  double seconds = 0;  // the bake's wall time
};

// Bakes a snapshot on `threads` threads (0: every core). Throws std::invalid_argument for
// settings out of range.
IndirectBake bakeIndirect(const SceneSnapshot& snapshot, const IndirectSettings& settings,
                          int threads);

class IndirectCache {
 public:
  explicit IndirectCache(size_t capacity) : capacity_(capacity) {}

  struct Found {
    std::shared_ptr<const IndirectBake> bake;
    bool cached = false;  // made by an earlier request (or one running when this one came)
  };
  // The bake of this snapshot, made now if no request made it before. A failed bake is not
  // kept (the next request tries again); its exception reaches every request that waited.
  Found get(const SceneSnapshot& snapshot, const IndirectSettings& settings, int threads);
  size_t size() const;

 private:
  struct Key {
    uint64_t version = 0;
    IndirectSettings settings;
    auto operator<=>(const Key&) const = default;
  };
  using Future = std::shared_future<std::shared_ptr<const IndirectBake>>;

  const size_t capacity_;
  mutable std::mutex mutex_;  // guards entries_, order_
  std::map<Key, Future> entries_;
  std::deque<Key> order_;  // insertion order: the oldest is evicted first
};

}  // namespace penumbra::server
