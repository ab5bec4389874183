// Engine::compactTrees: receivers whose DM-tree is mostly dead slots are cast afresh.
#include "core/engine/engine.h"
#include "core/illum/face_lookup.h"

namespace penumbra {

namespace {

// Below this many slots a tree is left alone: a fresh cast would save little.
constexpr size_t kCompactMinSlots = 1024;

bool mostlyDead(size_t slots, size_t live) {
  return slots > kCompactMinSlots && slots > Engine::kCompactSlotRatio * live;
}

}  // namespace

std::vector<FaceId> Engine::compactTrees(const std::vector<FaceId>& faces) {
  std::vector<FaceId> compacted;
  for (FaceId face : faces) {
    const auto found = receiverIndex_.find(face);
    if (found == receiverIndex_.end()) continue;
    Receiver& receiver = receivers_[found->second];
    const HalfEdgeMesh& mesh = receiver.tree.mesh();
    if (!mostlyDead(receiver.tree.nodeSlots(), receiver.tree.nodeCount()) &&
        !mostlyDead(mesh.vertexSlots(), mesh.vertexCount()) &&
        !mostlyDead(mesh.halfEdgeSlots(), mesh.halfEdgeCount()))
      continue;
    // Built beside the old one, then swapped in: a throw leaves the receiver as it was.
    Receiver fresh = makeReceiver(*findFace(scene_, face));
    std::map<FaceId, std::set<FaceId>> castOn = castOn_;
    std::map<FaceId, std::set<FaceId>> castBy = castBy_;
    forgetReceived(face);
    try {
      castAllOn(fresh);
      illuminate(fresh);
    } catch (...) {
      castOn_ = std::move(castOn);
      castBy_ = std::move(castBy);
      throw;
    }
    receiver = std::move(fresh);
    lastRelit_[face] = receiver.tree.vertices();
    displayMemo_.forget(face);
    compacted.push_back(face);
  }
  return compacted;
}

}  // namespace penumbra
