#include "server/part_diff.h"

#include "server/limits.h"

namespace penumbra::server {

namespace {

// Equal in all but the irradiance: a client holding one needs only the other's irradiance.
bool sameShape(const ReceiverMesh& a, const ReceiverMesh& b) {
  return a.normal == b.normal && a.positions == b.positions && a.classes == b.classes &&
         a.triangles == b.triangles;
}

}  // namespace

std::vector<PartKey> carryPartVersions(std::map<PartKey, const MeshPart*> before,
                                       const std::vector<MeshPart*>& fresh) {
  for (MeshPart* part : fresh) {
    const auto it = before.find(part->key);
    if (it == before.end()) continue;
    const MeshPart& old = *it->second;
    const bool sameShaped = old.mesh == part->mesh || sameShape(*old.mesh, *part->mesh);
    if (sameShaped) part->shapeVersion = old.shapeVersion;
    if (sameShaped && (old.mesh == part->mesh || old.mesh->irradiance == part->mesh->irradiance))
      part->version = old.version;
    before.erase(it);
  }
  std::vector<PartKey> left;
  for (const auto& [key, part] : before) left.push_back(key);
  return left;
}

void recordRemovals(SceneSnapshot& next, const std::set<PartKey>& live,
                    const std::vector<PartKey>& left, uint64_t version) {
  std::erase_if(next.removed, [&](const auto& entry) { return live.count(entry.first) > 0; });
  for (const PartKey& key : left) next.removed.emplace_back(key, version);
  if (version > kSinceWindow) next.forgetRemovedUpTo(version - kSinceWindow);
}

}  // namespace penumbra::server
