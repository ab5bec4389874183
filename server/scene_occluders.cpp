#include "server/scene_occluders.h"

#include <chrono>

namespace penumbra::server {

bool seenThroughBsdf(const Scene& scene, FaceId face) {
  const auto material = scene.findMaterial(scene.object(face.object).material);
  return material && scene.materials()[*material].type != MaterialType::Diffuse;
}

FrozenOccluders freezeOccluders(const Engine& engine, const OccluderIndexes& previous,
                                const std::set<FaceId>& redo) {
  const auto start = std::chrono::steady_clock::now();
  FrozenOccluders out;
  for (const Engine::Receiver& r : engine.receivers()) {
    if (!seenThroughBsdf(engine.scene(), r.face)) continue;
    const auto kept = previous.find(r.face);
    if (kept != previous.end() && !redo.count(r.face)) {
      out.indexes.emplace(r.face, kept->second);
    } else {
      out.indexes.emplace(r.face, std::make_shared<const OccluderIndex>(r.tree, r.frame));
      ++out.frozen;
    }
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

std::function<void(FaceId, const Vec3&, size_t, std::vector<FaceId>&)> occluderLookup(
    std::shared_ptr<const OccluderIndexes> indexes) {
  return [indexes = std::move(indexes)](FaceId face, const Vec3& p, size_t light,
                                        std::vector<FaceId>& out) {
    const auto it = indexes->find(face);
    if (it != indexes->end()) it->second->occluders(p, uint32_t(light), out);
  };
}

}  // namespace penumbra::server
