#include "core/render/dm_visibility.h"

#include <algorithm>

#include "core/illum/backprojection.h"

namespace penumbra {

OccludersFn dmOccluderLists(const Engine& engine) {
  return [&engine](FaceId face, const Vec3& p, size_t light, std::vector<FaceId>& out) {
    const Engine::Receiver* receiver = engine.receiver(face);
    if (!receiver) return;
    for (const OccluderEntry& e :
         receiver->tree.occluders(receiver->tree.locate(receiver->frame.to2D(p))))
      if (e.light == light && e.face != kLightPlaneOccluder) out.push_back(e.face);
  };
}

VisiblePiecesFn backprojectedPieces(const Scene& scene, OccludersFn occluders) {
  return [&scene, occluders = std::move(occluders)](uint32_t faceIndex, const Vec3& p, size_t light,
                                                    std::vector<Polygon3>& pieces) {
    const Face& face = scene.faces()[faceIndex];
    Backprojection backprojection(scene, light, p, face.plane.normal);
    if (!backprojection.applies()) return;
    std::vector<FaceId> candidates;
    occluders(face.id, p, light, candidates);
    for (const FaceId& id : candidates) backprojection.occludeId(id);
    pieces = backprojection.visiblePieces();
  };
}

}  // namespace penumbra
