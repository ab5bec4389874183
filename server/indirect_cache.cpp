#include "server/indirect_cache.h"

#include <chrono>

#include "core/gi/sensor_gi.h"
#include "core/raycast/ray_scene.h"
#include "core/util/parallel.h"

namespace penumbra::server {

IndirectBake bakeIndirect(const SceneSnapshot& snapshot, const IndirectSettings& settings,
                          int threads) {
  const auto start = std::chrono::steady_clock::now();
  IndirectBake bake;
  bake.version = snapshot.version;
  bake.settings = settings;
  const RayScene rays(snapshot.scene);
  bake.mesh = gi::vertexIndirect(snapshot.scene, rays, snapshot.mesh(), settings.sensorSize,
                                 settings.bounces, Parallel(threads));
  // mesh() concatenates each receiver's parts in order: a part starts where the previous ended.
  bake.partReceiver.resize(snapshot.parts.size());
  bake.partOffset.resize(snapshot.parts.size());
  for (size_t i = 0, receiver = 0, offset = 0; i < snapshot.parts.size(); ++i) {
    if (i > 0 && !(snapshot.parts[i].key.receiver == snapshot.parts[i - 1].key.receiver)) {
      ++receiver;
      offset = 0;
    }
    bake.partReceiver[i] = receiver;
    bake.partOffset[i] = offset;
    offset += snapshot.parts[i].mesh->positions.size();
  }
  bake.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return bake;
}

IndirectCache::Found IndirectCache::get(const SceneSnapshot& snapshot,
                                        const IndirectSettings& settings, int threads) {
  const Key key{snapshot.version, settings};
  std::promise<std::shared_ptr<const IndirectBake>> promise;
  Future found;
  {
    std::lock_guard lock(mutex_);
    if (const auto it = entries_.find(key); it != entries_.end()) {
      found = it->second;
    } else {
      entries_.emplace(key, promise.get_future().share());
      order_.push_back(key);
      while (order_.size() > capacity_) {  // waiters on an evicted bake hold their own future
        entries_.erase(order_.front());
        order_.pop_front();
      }
    }
  }
  if (found.valid()) return {found.get(), true};  // waits while another request bakes it
  try {
    auto bake = std::make_shared<const IndirectBake>(bakeIndirect(snapshot, settings, threads));
    promise.set_value(bake);
    return {bake, false};
  } catch (...) {
    promise.set_exception(std::current_exception());
    std::lock_guard lock(mutex_);
    entries_.erase(key);
    std::erase(order_, key);
    throw;
  }
}

size_t IndirectCache::size() const {
  std::lock_guard lock(mutex_);
  return entries_.size();
}

}  // namespace penumbra::server
